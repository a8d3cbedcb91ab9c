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
pub mod build;
pub mod error;
pub mod input;
pub mod io;
pub mod kernel;
pub mod measure;
pub mod mesh;
pub mod overlap;
pub mod params;
pub mod pipeline;
pub mod skeleton;

pub use error::{Error, Result, SwcError};
pub use input::morphology::{Morphology, Soma, SomaKind, Tree};
pub use measure::check::MeshReport;
pub use mesh::{BuildStats, Mesh, MeshView};
pub use params::Params;
pub use pipeline::{mesh_morphology, mesh_swc};

#[cfg(feature = "python")]
mod python;
