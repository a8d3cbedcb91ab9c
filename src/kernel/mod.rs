//! The geometry kernel: what every stage builds on, none of it about
//! neurons.
//!
//! - [`vector`]: the array vectors meshes store and their arithmetic (the
//!   construction computes with glam's `DVec3`);
//! - [`predicates`]: exact orientation predicates and the triangle tests
//!   built on them, which decide every question of topology;
//! - [`round_cone`]: the convex hull of two spheres, the skeleton's volume;
//! - [`bvh`]: a bounding-volume hierarchy over boxes;
//! - [`planar`]: planar triangulations (ear clipping, spade's constrained
//!   Delaunay);
//! - [`disjoint_sets`]: union-find and the components of a triangle soup;
//! - [`hash`], [`bits`]: a fast hasher for computed keys, a bit set;
//! - [`parallel`]: order-keeping parallel maps, serial without rayon;
//! - [`rng`]: the one seeded random generator.
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
