//! Construction.
pub mod coverage;
pub mod filler;
pub mod plan;
pub mod soma;
pub mod splice;
pub mod star_hull;
pub mod surface;
pub mod tube;
