//! Branch tubes: contours connected into a surface, closed by tip caps
//! (paper §3.2, "Contour Connection").
//!
//! * **Connection** ([`band`]): each band joins two contours by the
//!   paper's minimum included-angle rule, in a form that never folds.
//! * **Caps** ([`cap`]): a free end is closed by a dome inside the end
//!   sample's sphere, the round cone's end cap.
//!
//! Which contours are kept, and where a branch splits into pieces, is decided
//! in [`crate::build::tube::pieces`].
//!
//! Winding: contours run counter-clockwise about the direction of travel, and a
//! band's triangles are (a_i, a_{i+1}, b_j) and (a_i, b_{j+1}, b_j), which face
//! outward.

pub mod band;
pub mod cap;
mod guard;
pub mod pieces;

use glam::DVec3;

use crate::build::surface::{Offset, Surface};
use crate::skeleton::contour;
use crate::skeleton::frame::DiscFrame;
use crate::skeleton::track::Track;

/// One contour as placed in the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ring {
    /// Centre.
    pub center: DVec3,
    /// Unit normal: the direction of travel.
    pub normal: DVec3,
    /// Unit direction of the first vertex.
    pub u: DVec3,
    /// Polygon radius (corrected, see [`contour::polygon_radius`]).
    pub radius: f64,
    /// The skeleton radius at this point.
    pub skeleton_radius: f64,
    /// Number of vertices.
    pub m: u32,
    /// Index of the first vertex in the surface; the others follow.
    pub first: u32,
    /// Morphology sample the ring's vertices are labelled with.
    pub label: u32,
    /// Position along the branch: index into the branch's original points of the
    /// nearest one.
    pub source: u32,
    /// Index of the resampled point it was made from.
    pub resampled: u32,
}

impl Ring {
    /// Surface index of vertex `j` (taken modulo m).
    #[inline]
    pub fn vertex(&self, j: u32) -> u32 {
        self.first + j % self.m
    }

    /// The disc of this ring, for clearance tests.
    pub fn disc(&self) -> DiscFrame {
        DiscFrame {
            center: self.center,
            normal: self.normal,
            radius: self.radius,
        }
    }
}

/// How many of a tube's first contours the pipeline keeps once the tube is
/// built ([`Tube::rings`]): splicing tries its C_1sec among them and the
/// somas join the first. The others are let go, because nothing after the
/// tube reads them, and a million-sample tree's 2.7 million rings (0.3 GB,
/// in small blocks grown by doubling) stayed resident through the overlap
/// pass.
pub const KEPT_RINGS: usize = 40;

/// A closed or open tube along one piece of a branch.
#[derive(Debug, Clone, PartialEq)]
pub struct Tube {
    /// Index of the branch it belongs to.
    pub branch: u32,
    /// The kept contours, in order of travel: all of them as
    /// [`crate::build::tube::pieces::build_pieces`] builds the tube, the first
    /// [`KEPT_RINGS`] of them once appended to the cell's surface
    /// ([`Tube::appended_at`]).
    pub rings: Vec<Ring>,
    /// First triangle of the band between ring i and ring i + 1; one more entry
    /// marks the end of the last band.
    pub bands: Vec<u32>,
    /// Triangles of the cap before the first ring (empty range if open).
    pub start_cap: std::ops::Range<u32>,
    /// Triangles of the cap after the last ring.
    pub end_cap: std::ops::Range<u32>,
    /// Vertices of the start cap (rings and apex), empty if open.
    pub start_cap_vertices: std::ops::Range<u32>,
    /// All its triangles (caps and bands), contiguous in the surface.
    pub tris: std::ops::Range<u32>,
    /// The point it grows out of: the branch point of a secondary, the end of
    /// the previous piece for a later piece (splicing aims its ray there).
    pub anchor: DVec3,
}

impl Tube {
    /// The tube as it stands in the surface its own was appended to at
    /// `offset`, keeping its first [`KEPT_RINGS`] rings.
    pub fn appended_at(mut self, offset: Offset) -> Tube {
        self.rings.truncate(KEPT_RINGS);
        self.rings.shrink_to_fit();
        for r in &mut self.rings {
            r.first = offset.vertex(r.first);
        }
        for b in &mut self.bands {
            *b = offset.triangle(*b);
        }
        self.start_cap = offset.triangle_range(self.start_cap);
        self.end_cap = offset.triangle_range(self.end_cap);
        self.start_cap_vertices = offset.vertex_range(self.start_cap_vertices);
        self.tris = offset.triangle_range(self.tris);
        self
    }
}

/// Places the contour of track point `i` into the surface, with first-vertex
/// direction `u`.
pub fn place_ring(
    surface: &mut Surface,
    track: &Track,
    i: usize,
    u: DVec3,
    labels: &[u32],
) -> Ring {
    let s = &track.samples[i];
    let m = track.counts[i];
    let label = labels[s.source as usize];
    let first = surface.pos.len() as u32;
    for p in contour::ring(s.pos, s.tangent, u, track.radii[i], m) {
        surface.vertex(p, label);
    }
    Ring {
        center: s.pos,
        normal: s.tangent,
        u,
        radius: track.radii[i],
        skeleton_radius: s.radius,
        m,
        first,
        label,
        source: s.source,
        resampled: i as u32,
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::band::connect;
    use super::*;
    use crate::mesh::BuildStats;
    use crate::params::Params;

    /// A straight track of `n` points 2 apart, radius `r`.
    pub(crate) fn straight(n: usize, r: f64) -> Track {
        let pts: Vec<DVec3> = (0..n)
            .map(|i| DVec3::new(i as f64 * 2.0, 0.0, 0.0))
            .collect();
        Track::new(&pts, &vec![r; n], &Params::DEFAULT, None)
    }

    #[test]
    fn connecting_different_counts_makes_m_plus_n_triangles() {
        let track = straight(2, 1.0);
        let mut s = Surface::default();
        let a = place_ring(&mut s, &track, 0, track.frames[0], &[0, 1]);
        let mut b = place_ring(&mut s, &track, 1, track.frames[1], &[0, 1]);
        // Rebuild b with 18 vertices.
        s.pos.truncate(b.first as usize);
        s.label.truncate(b.first as usize);
        b.m = 18;
        for p in contour::ring(b.center, b.normal, b.u, b.radius, 18) {
            s.vertex(p, 1);
        }
        connect(&mut s, &a, &b);
        assert_eq!(s.tris.len(), a.m as usize + 18);
        // Every edge of the band is used once or twice: a valid strip.
        let r = s.into_mesh(BuildStats::default()).check();
        assert_eq!(r.nonmanifold_edges, 0);
        assert_eq!(r.boundary_edges, a.m as usize + 18);
    }
}
