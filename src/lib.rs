//! # neuromesh
//!
//! Closed, 2-manifold triangle meshes of neuron membranes from SWC skeletons,
//! following "Reconstructing the Surface Mesh Representation for Single Neuron"
//! (branch identification, Catmull-Rom resampling, adaptive contours pushed
//! forward along each branch, contour connection, splicing at branch points and a
//! soma triangulated from a sphere point set).
//!
//! ```text
//! SWC text ─parse─▶ Morphology ─split─▶ Branches ─resample─▶ contours ─connect─▶ tubes
//!          ─splice─▶ junctions ─soma (spade CDT)─▶ Mesh ─▶ OBJ / PLY / STL, numpy
//! ```
//!
//! Every stage is a function from the previous stage's value to the next; SWC ids
//! exist only in [`swc`] and [`Morphology`], everything after uses dense sample
//! indices. Errors are values ([`Error`]) that name the file, line and reason.

#![forbid(unsafe_code)]

pub mod batch;
mod bits;
pub mod blob;
pub mod branch;
pub mod bvh;
pub mod check;
pub mod contour;
pub mod crofton;
pub mod cut;
pub mod error;
pub mod filler;
pub mod geom;
pub mod grid;
pub mod hash;
pub mod info;
pub mod io;
pub mod measures;
pub mod mesh;
pub mod mesher;
pub mod morphology;
pub mod overlap;
pub mod parallel;
pub mod params;
pub mod piece;
pub mod planar;
pub mod plausibility;
mod proof;
pub mod recut;
pub mod soma;
pub mod splice;
pub mod spline;
pub mod starts;
pub mod straight;
pub mod surface;
pub mod swc;
pub mod synthetic;
pub mod track;
pub mod tube;
pub mod union;
pub mod volume;

pub use check::MeshReport;
pub use error::{Error, Result, SwcError};
pub use mesh::{BuildStats, Mesh, MeshView};
pub use mesher::{mesh_morphology, mesh_swc};
pub use morphology::{Morphology, Soma, SomaKind, Tree};
pub use params::Params;

#[cfg(feature = "python")]
mod python;
