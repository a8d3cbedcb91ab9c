//! Measures.
pub mod check;
pub mod report;
pub mod crofton;
pub mod skeleton;
pub mod summary;
pub mod union;
