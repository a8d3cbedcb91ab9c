//! The frame a cell is built in: its samples as vectors, scaled, moved near
//! the origin when the cell lies far from it, and with radii raised to a
//! floor that keeps the f32 output's contours distinct.

use glam::DVec3;

use crate::input::morphology::Morphology;
use crate::params::Params;

/// Radii are never below this fraction of the largest coordinate (in the
/// frame the cell is built in, [`crate::mesh::frame_origin`]), so the f32
/// output keeps a contour's vertices distinct.
pub const RELATIVE_RADIUS_FLOOR: f64 = 1e-5;

/// The point a morphology scaled by `scale` is built around
/// ([`crate::mesh::frame_origin`] of the box of its spheres).
pub fn frame_origin_of(morphology: &Morphology, scale: f64) -> [f64; 3] {
    let (lo, hi) = morphology.bounds();
    crate::mesh::frame_origin(lo.map(|c| c * scale), hi.map(|c| c * scale))
}

/// Positions and effective radii of the samples, ready for geometry.
#[derive(Debug, Clone)]
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
        let floor = floor_at(extent, params.min_radius);
        let radius = m.radii().iter().map(|&r| r.max(floor)).collect();
        Geometry { pos, radius }
    }
}

/// The radius floor for a cell whose largest coordinate, in the frame it is
/// built in, is `extent`: `max(min_radius, 1e-5 × extent)`.
pub fn floor_at(extent: f64, min_radius: f64) -> f64 {
    min_radius.max(RELATIVE_RADIUS_FLOOR * extent)
}

/// The radius floor [`Geometry::new`] applies to `morphology` meshed with
/// `params` (scaled, and built around [`frame_origin_of`]), found without
/// building the frame: for the checks made before meshing.
pub fn radius_floor(morphology: &Morphology, params: &Params) -> f64 {
    let scale = params.scale;
    let origin = frame_origin_of(morphology, scale);
    let extent = morphology
        .positions()
        .iter()
        .flat_map(|p| (0..3).map(move |k| (p[k] * scale - origin[k]).abs()))
        .fold(0.0, f64::max);
    floor_at(extent, params.min_radius)
}
