//! The pipeline end to end: a morphology in, a closed mesh out.
//!
//! [`mesh_morphology`] meshes a star-shaped blob whole ([`star_hull`]);
//! any other cell is constructed ([`construct`], stages 1 to 5) and its
//! crossing parts united by the overlap pass ([`crate::overlap`], stage 6),
//! constructed again at a safer reach or without the fillers the pass
//! could not unite where it leaves crossings ([`retry`]).

pub mod budget;
pub mod repairs;
mod retry;
mod shells;

pub use retry::unite;

use crate::build::{FIRST_REACH, construct, star_hull};
use crate::error::Result;
use crate::input::morphology::Morphology;
use crate::mesh::Mesh;
use crate::params::Params;
use crate::skeleton::geometry::frame_origin_of;

/// Meshes an SWC file with `params` (reading, cleaning and meshing).
///
/// # Errors
/// [`crate::Error::Io`] or [`crate::Error::Swc`] for the file,
/// [`crate::Error::InvalidParam`] for a bad parameter.
///
/// # Example
/// ```
/// let mesh = neuromesh::mesh_swc("tests/data/y_bifurcation.swc", &neuromesh::Params::default())?;
/// assert!(mesh.check().is_closed());
/// # Ok::<(), neuromesh::Error>(())
/// ```
pub fn mesh_swc(path: impl AsRef<std::path::Path>, params: &Params) -> Result<Mesh> {
    params.validate()?;
    mesh_morphology(&Morphology::from_swc(path)?, params)
}

/// Meshes a morphology with `params`.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter, [`crate::Error::Swc`]
/// for a cell estimated to need more than `params.face_limit` triangles
/// (estimated by [`crate::estimate`]), or for values no cell has.
pub fn mesh_morphology(morphology: &Morphology, params: &Params) -> Result<Mesh> {
    params.validate()?;
    budget::check(morphology, params)?;
    // A union of round cones that is one star-shaped blob (radius codes
    // swelling every sphere past the cell) is meshed whole ([`crate::build::star_hull`]).
    let origin = frame_origin_of(morphology, params.scale);
    let mut mesh = match star_hull::mesh(morphology, params.scale, origin) {
        Some(mut mesh) => {
            mesh.origin = origin;
            mesh
        }
        None => unite(
            morphology,
            params,
            construct(morphology, params, FIRST_REACH)?,
        )?,
    };
    repairs::count(morphology, params, &mut mesh.stats);
    Ok(mesh)
}
