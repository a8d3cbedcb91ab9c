//! Measures.
pub mod check;
pub mod crofton;
pub mod report;
pub mod skeleton;
pub mod summary;
pub mod union;
