//! The geometry kernel: what every stage builds on and nothing in it knows
//! about neurons.
pub mod bits;
pub mod bvh;
pub mod disjoint_sets;
pub mod hash;
pub mod parallel;
pub mod planar;
pub mod predicates;
pub mod rng;
pub mod round_cone;
pub mod vector;
