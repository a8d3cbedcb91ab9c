//! The pipeline, end to end: morphology → branches → tubes → mesh.
//!
//! Branch tubes are independent, so they are built in parallel (each into its
//! own [`Surface`]) and appended in branch order, which keeps the output
//! identical whatever the number of threads.

use glam::DVec3;

use crate::branch::{self, Branch};
use crate::error::Result;
use crate::mesh::{BuildStats, Mesh};
use crate::morphology::Morphology;
use crate::params::Params;
use crate::piece::{self, Caps};
use crate::surface::Surface;
use crate::track::Track;
use crate::tube::Tube;

/// Radii are never below this fraction of the largest coordinate, so the f32
/// output keeps a contour's vertices distinct.
pub const RELATIVE_RADIUS_FLOOR: f64 = 1e-5;

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
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn mesh_morphology(morphology: &Morphology, params: &Params) -> Result<Mesh> {
    let (surface, _, _, stats) = build(morphology, params)?;
    Ok(surface.into_mesh(stats))
}

/// The whole construction with its intermediate structures (branches and tubes
/// with their rings), for inspection and debugging tools.
///
/// # Errors
/// [`crate::Error::InvalidParam`] for a bad parameter.
pub fn build(
    morphology: &Morphology,
    params: &Params,
) -> Result<(Surface, Vec<Branch>, Vec<Tube>, BuildStats)> {
    params.validate()?;
    let m = morphology.scaled(params.scale)?;
    let geometry = Geometry::new(&m, params);
    let branches = branch::identify(&m, params.angle_threshold);
    let jobs: Vec<(u32, &Branch)> = branches
        .iter()
        .enumerate()
        .map(|(i, b)| (i as u32, b))
        .collect();
    let built: Vec<(Surface, Vec<Tube>, u32)> =
        crate::parallel::map(&jobs, |&(id, b)| build_branch(&geometry, b, id, params));
    let mut surface = Surface::with_capacity(built.iter().map(|(s, _, _)| s.pos.len()).sum());
    let mut tubes: Vec<Tube> = Vec::new();
    let mut stats = BuildStats {
        branches: branches.len() as u32,
        ..BuildStats::default()
    };
    for (local, local_tubes, skipped) in built {
        let (v0, t0) = surface.append(&local);
        stats.contours_skipped += skipped;
        for mut t in local_tubes {
            for r in &mut t.rings {
                r.first += v0;
            }
            for b in &mut t.bands {
                *b += t0;
            }
            t.start_cap = t.start_cap.start + t0..t.start_cap.end + t0;
            t.end_cap = t.end_cap.start + t0..t.end_cap.end + t0;
            t.start_cap_vertices = t.start_cap_vertices.start + v0..t.start_cap_vertices.end + v0;
            tubes.push(t);
        }
    }
    Ok((surface, branches, tubes, stats))
}

/// Positions and effective radii of the samples, ready for geometry.
pub struct Geometry {
    /// Sample positions.
    pub pos: Vec<DVec3>,
    /// Radii after the floor.
    pub radius: Vec<f64>,
}

impl Geometry {
    /// Positions as vectors and radii raised to the floor
    /// `max(min_radius, 1e-5 × largest coordinate)`.
    pub fn new(m: &Morphology, params: &Params) -> Geometry {
        let pos: Vec<DVec3> = m
            .positions()
            .iter()
            .map(|p| DVec3::from_array(*p))
            .collect();
        let extent = pos
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0, f64::max);
        let floor = params.min_radius.max(RELATIVE_RADIUS_FLOOR * extent);
        let radius = m.radii().iter().map(|&r| r.max(floor)).collect();
        Geometry { pos, radius }
    }
}

fn build_branch(g: &Geometry, b: &Branch, id: u32, params: &Params) -> (Surface, Vec<Tube>, u32) {
    let points: Vec<DVec3> = b.samples.iter().map(|&s| g.pos[s as usize]).collect();
    let radii: Vec<f64> = b.samples.iter().map(|&s| g.radius[s as usize]).collect();
    let track = Track::new(&points, &radii, params, None);
    let mut surface = Surface::with_capacity(track.counts.iter().map(|&m| m as usize).sum());
    let caps = Caps {
        first_start: true,
        later_starts: true,
        rings: params.cap_rings,
    };
    let (tubes, skipped) = piece::build_pieces(&mut surface, &track, &b.samples, id, 0, caps);
    (surface, tubes, skipped)
}
