//! The frame a cell is built in: its samples as vectors, scaled, moved near
//! the origin when the cell lies far from it, and with radii raised to a
//! floor that keeps the f32 output's contours distinct.
//!
//! The floor follows the cell's size, not its place: `1e-5` of the longest
//! side of the box of its spheres. The frame keeps every coordinate within
//! 1.5 sides of its origin ([`crate::mesh::frame_origin`]), so a contour of
//! floor radius still spans dozens of f32 steps wherever the cell lies.

use glam::DVec3;

use crate::input::morphology::Morphology;
use crate::params::Params;

/// Radii are never below this fraction of the longest side of the cell's
/// box, so the f32 output keeps a contour's vertices distinct.
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
    /// `max(min_radius, 1e-5 × the longest side of the box)` of `m`, a
    /// morphology already scaled.
    pub fn new(m: &Morphology, params: &Params) -> Geometry {
        let pos: Vec<DVec3> = m
            .positions()
            .iter()
            .map(|p| DVec3::from_array(*p))
            .collect();
        let floor = floor_at(longest_side(m, 1.0), params.min_radius);
        let radius = m.radii().iter().map(|&r| r.max(floor)).collect();
        Geometry { pos, radius }
    }
}

/// The radius floor for a cell whose box's longest side is `side`:
/// `max(min_radius, 1e-5 × side)`.
pub fn floor_at(side: f64, min_radius: f64) -> f64 {
    min_radius.max(RELATIVE_RADIUS_FLOOR * side)
}

/// The longest side of the box of `morphology`'s spheres scaled by `scale`.
pub fn longest_side(morphology: &Morphology, scale: f64) -> f64 {
    let (lo, hi) = morphology.bounds();
    (0..3).map(|a| (hi[a] - lo[a]) * scale).fold(0.0, f64::max)
}

/// The radius floor [`Geometry::new`] applies to `morphology` meshed with
/// `params`, found without building the frame: for the checks made before
/// meshing.
pub fn radius_floor(morphology: &Morphology, params: &Params) -> f64 {
    floor_at(longest_side(morphology, params.scale), params.min_radius)
}
