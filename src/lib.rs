//! # neuromesh
//!
//! Closed, 2-manifold triangle meshes of neuron membranes from SWC skeletons,
//! following "Reconstructing the Surface Mesh Representation for Single Neuron"
//! (branch identification, Catmull-Rom resampling, adaptive contours pushed
//! forward along each branch, contour connection, splicing at branch points and
//! a soma triangulated from a sphere point set), made closed and free of
//! self-intersections by an overlap pass that keeps the boundary of the union
//! of parts that cross.
//!
//! ```
//! let mesh = neuromesh::mesh_swc("tests/data/y_bifurcation.swc", &neuromesh::Params::default())?;
//! assert!(mesh.check().is_valid());
//! neuromesh::io::write(std::env::temp_dir().join("y.ply"), &mesh)?;
//! # Ok::<(), neuromesh::Error>(())
//! ```
//!
//! ## The pipeline
//!
//! Every stage is a function from the previous stage's value to the next.
//! SWC ids exist only in the input stage; everything after it uses dense
//! sample indices.
//!
//! | stage | module | paper | produces |
//! | --- | --- | --- | --- |
//! | 0. read | `input::swc`, `input::morphology` | — | `SwcFile`, [`Morphology`] |
//! | 1. skeleton | `skeleton` (`geometry`, `branch`, `spline`, `tangents`, `frame`, `contour`, `thinning`, `track`) | §3.1; §3.2, formulas 1–3 | `Skeleton`: branches and their `Track`s |
//! | 2. plan | `build::plan` (with `build::coverage`) | §3.2 (contours inside the primary), §3.3 (trunks) | `Starts` |
//! | 3. tubes | `build::tubes`, `build::tube` (`pieces`, `guard`, `band`, `cap`) | §3.2, contour connection, caps | `Tubes` |
//! | — fillers chosen | `build::filler` | beyond the paper | `FillerPlan` |
//! | 4. somas | `build::soma`, run by `build::join_somas` | §3.3 | `Open` |
//! | 5. splicing | `build::splice` (`splicer`, `region`, `bridge`, `fallback`, `index`) | §3.2, Fig. 5–6 | `Spliced` |
//! | 5b. fillers | `build::filler` (`gain`, `cone`, `select`), run by `build::build_fillers` | beyond the paper | `Construction` |
//! | 6. overlaps | `overlap` (`pairs`, `cut`, `retriangulate`, `settle`, `patches`, `boundary`, `verify`, `assembly`) | beyond the paper | [`Mesh`] |
//! | — retries | `pipeline` (`retry`, `shells`) | beyond the paper | [`Mesh`] |
//! | — star hull | `build::star_hull` | beyond the paper (radius codes) | [`Mesh`] |
//! | out | [`io`], `measure::check` | — | OBJ, PLY, STL; [`MeshReport`] |
//!
//! Beside the stages, `measure` holds the quality report and the reference a
//! mesh is judged against (the exact union of the skeleton's round cones), and
//! `kernel` the geometry every stage builds on (vectors, exact predicates,
//! disjoint sets, the round cone, a BVH, planar triangulation, hashing, bit
//! sets, the parallel shim, the seeded random generator). `ARCHITECTURE.md`
//! draws the pipeline with the types between the stages.
//!
//! The stage modules are private; the `internals` feature makes them public
//! for the examples, benchmarks and tests, with no promise of stability.
//!
//! Errors are values ([`Error`]) that name the file, line and reason.

#![forbid(unsafe_code)]

mod build;
mod error;
mod input;
mod kernel;
mod measure;
mod mesh;
mod overlap;
mod params;
mod pipeline;
mod skeleton;

pub mod batch;
#[cfg(feature = "cli")]
pub mod cli;
pub mod io;

pub use error::{Error, Result, SwcError};
pub use input::morphology::{Cleaning, Morphology, NO_PARENT, Soma, SomaKind, Tree};
pub use measure::fidelity::{Deviation, Fidelity, MAX_DEVIATION, P95_DEVIATION};
pub use measure::report::MeshReport;
pub use measure::skeleton::SkeletonMeasures;
pub use measure::summary::Summary;
pub use measure::union::UnionMeasures;
pub use mesh::{BuildStats, Mesh, MeshView, frame_origin};
pub use params::{
    DEFAULT_ANGLE_THRESHOLD, DEFAULT_CAP_RINGS, DEFAULT_FACE_LIMIT, DEFAULT_K1,
    DEFAULT_MAX_VERTICES, DEFAULT_MIN_RADIUS, DEFAULT_MIN_VERTICES, DEFAULT_RESOLUTION,
    DEFAULT_SCALE, PARAM_NAMES, Params,
};
pub use pipeline::budget::{Estimate, estimate};
pub use pipeline::repairs::repairs;
pub use pipeline::{mesh_morphology, mesh_swc};

#[cfg(feature = "internals")]
pub mod internals {
    //! The stages' own modules, public for the examples, benchmarks and
    //! tests (the `internals` feature). Not a stable API: anything here may
    //! change in any release.

    /// Stages 2 to 5: the construction.
    pub mod build {
        pub use crate::build::*;
    }
    /// Stage 0: SWC text and arrays to a morphology.
    pub mod input {
        pub use crate::input::*;
    }
    /// The geometry kernel.
    pub mod kernel {
        pub use crate::kernel::*;
    }
    /// The quality report and the union of round cones.
    pub mod measure {
        pub use crate::measure::*;
    }
    /// The output type.
    pub mod mesh {
        pub use crate::mesh::*;
    }
    /// Stage 6: the overlap pass.
    pub mod overlap {
        pub use crate::overlap::*;
    }
    /// The pipeline end to end, with its retries.
    pub mod pipeline {
        pub use crate::pipeline::*;
    }
    /// Stage 1: the skeleton made ready for contours.
    pub mod skeleton {
        pub use crate::skeleton::*;
    }
}

#[cfg(feature = "python")]
mod python;
