//! Branch tubes: contours connected into a surface, closed by tip caps
//! (paper §3.2, "Contour Connection").
//!
//! * **Connection.** Contour C_i is projected on the plane through P_i with C_{i+1}'s
//!   normal, which makes the two contours parallel. Starting from the two first
//!   vertices (which correspond, thanks to the push-forward frames), each step
//!   adds the triangle whose new diagonal makes the smaller angle with P_iP_{i+1}:
//!   the straighter one. The result has m_i + m_{i+1} triangles; the original
//!   coordinates are used for the output.
//! * **Caps.** A free end is closed by a dome inside the end sample's sphere:
//!   `cap_rings` rings at heights r·sin φ and radii r·cos φ (φ evenly spaced in
//!   (0, π/2)) and an apex at distance r: a polygonal hemisphere, the round
//!   cone's end cap. With `cap_rings = 0` the end is a flat fan.
//! * **Pieces.** A branch whose remaining contours can never clear the last kept
//!   one (the path turned back on itself, a hairpin tighter than the tube) is
//!   split: the piece so far is capped and the rest continues as a new piece
//!   attached to it, which splicing joins like a secondary branch.
//!
//! Winding: contours run counter-clockwise about the direction of travel, and a
//! band's triangles are (a_i, a_{i+1}, b_j) and (a_i, b_{j+1}, b_j), which face
//! outward.

use glam::DVec3;

use crate::contour::{self, DiscFrame};
use crate::params::Params;
use crate::spline::{self, Sample};
use crate::surface::Surface;

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

/// A closed or open tube along one piece of a branch.
#[derive(Debug, Clone, PartialEq)]
pub struct Tube {
    /// Index of the branch it belongs to.
    pub branch: u32,
    /// The kept contours, in order of travel.
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
}

/// The resampled, framed points of a branch with their contour sizes.
#[derive(Debug, Clone)]
pub struct Track {
    /// Resampled points.
    pub samples: Vec<Sample>,
    /// First-vertex direction per point.
    pub frames: Vec<DVec3>,
    /// Vertex count per point.
    pub counts: Vec<u32>,
    /// Polygon radius per point.
    pub radii: Vec<f64>,
    /// Edge length used by formulas 1 and 3 (r_avg / resolution).
    pub edge: f64,
}

impl Track {
    /// Resamples and frames a branch given its points and radii.
    pub fn new(points: &[DVec3], radii: &[f64], params: &Params, u0: Option<DVec3>) -> Track {
        let r_avg = radii.iter().sum::<f64>() / radii.len() as f64;
        let edge = r_avg / params.resolution;
        let samples = spline::resample(points, radii, edge, params.k1);
        let start_u = u0
            .map(|u| u - u.dot(samples[0].tangent) * samples[0].tangent)
            .filter(|u| u.length_squared() > 1e-12)
            .map_or_else(
                || contour::any_perpendicular(samples[0].tangent),
                DVec3::normalize,
            );
        let frames = contour::frames(&samples, start_u);
        let counts: Vec<u32> = samples
            .iter()
            .map(|s| {
                contour::vertex_count(s.radius, edge, params.min_vertices, params.max_vertices)
            })
            .collect();
        let radii = samples
            .iter()
            .zip(&counts)
            .map(|(s, &m)| contour::polygon_radius(s.radius, m))
            .collect();
        Track {
            samples,
            frames,
            counts,
            radii,
            edge,
        }
    }

    /// The disc of point `i`.
    pub fn disc(&self, i: usize) -> DiscFrame {
        DiscFrame {
            center: self.samples[i].pos,
            normal: self.samples[i].tangent,
            radius: self.radii[i],
        }
    }

    /// Clearance margin between consecutive kept contours.
    pub fn margin(&self, a: usize, b: usize) -> f64 {
        0.02 * self.radii[a].min(self.radii[b])
    }
}

/// Chooses which contours to keep, in pieces. Each piece is a list of point
/// indices whose consecutive discs clear each other. `first` is the first point
/// to consider (earlier ones are inside something else). Also returns how many
/// contours were skipped.
pub fn select_contours(track: &Track, first: usize) -> (Vec<Vec<usize>>, u32) {
    let n = track.samples.len();
    let mut pieces = Vec::new();
    let mut skipped = 0u32;
    let mut start = first.min(n - 1);
    loop {
        let mut kept = vec![start];
        let mut split_at = None;
        // A point known to lie ahead of the last kept contour, so scanning on is
        // worthwhile even though the path has turned back for now.
        let mut ahead: Option<(usize, usize)> = None;
        for k in start + 1..n {
            let j = kept[kept.len() - 1];
            if track.disc(j).clears(&track.disc(k), track.margin(j, k)) {
                kept.push(k);
                continue;
            }
            skipped += 1;
            if track.samples[k].tangent.dot(track.samples[j].tangent) >= 0.0 {
                continue;
            }
            let known = matches!(ahead, Some((jj, w)) if jj == j && w > k);
            if !known {
                match point_ahead(track, j, k) {
                    Some(w) => ahead = Some((j, w)),
                    None => {
                        split_at = Some(k);
                        break;
                    }
                }
            }
        }
        let last = kept[kept.len() - 1];
        pieces.push(kept);
        match split_at {
            // Split only when the rest of the branch is worth a piece of its own.
            Some(k)
                if track.samples[n - 1].pos.distance(track.samples[last].pos)
                    > track.samples[last].radius =>
            {
                start = k;
            }
            _ => break,
        }
    }
    (pieces, skipped)
}

/// The first point after `k` that lies ahead of point `j`'s disc and moves
/// forward, if any: a later contour there may still clear `j`.
fn point_ahead(track: &Track, j: usize, k: usize) -> Option<usize> {
    let dj = track.disc(j);
    (k + 1..track.samples.len()).find(|&i| {
        let s = &track.samples[i];
        (s.pos - dj.center).dot(dj.normal) > dj.radius && s.tangent.dot(dj.normal) > 0.0
    })
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

/// Connects ring `a` (behind) to ring `b` (in front) with the minimum
/// included-angle rule, starting from their first vertices.
pub fn connect(surface: &mut Surface, a: &Ring, b: &Ring) {
    let ta = uniform_angles(a.m);
    let tb = uniform_angles(b.m);
    connect_loops(
        surface,
        &ring_loop(a),
        &ta,
        &ring_loop(b),
        &tb,
        a.center,
        b.center,
        b.normal,
    );
}

/// The vertex indices of a ring in order.
pub fn ring_loop(r: &Ring) -> Vec<u32> {
    (0..r.m).map(|j| r.first + j).collect()
}

/// Angular positions of the vertices of an m-gon.
pub fn uniform_angles(m: u32) -> Vec<f64> {
    (0..m)
        .map(|j| std::f64::consts::TAU * f64::from(j) / f64::from(m))
        .collect()
}

/// Connects two vertex loops that run the same way round, `a` behind `b`.
///
/// `ta` and `tb` are the loops' angular positions about the common axis,
/// increasing from 0 at the corresponding first vertices. The paper's rule
/// chooses each triangle: `a` is projected on the plane through `ca` with normal
/// `nb` (making the loops parallel) and the diagonal with the smaller angle to the
/// axis `ca → cb` wins. Where that rule is ill-posed (nearly flat bands, where
/// every diagonal is almost perpendicular to the axis) it could fold the band,
/// so a choice may not let one loop overtake the other by more than half a step
/// in angle; within that the paper's rule decides.
pub fn connect_loops(
    surface: &mut Surface,
    a: &[u32],
    ta: &[f64],
    b: &[u32],
    tb: &[f64],
    ca: DVec3,
    cb: DVec3,
    nb: DVec3,
) {
    let (ma, mb) = (a.len(), b.len());
    let axis = cb - ca;
    let axis_len = axis.length().max(1e-300);
    let pa: Vec<DVec3> = a
        .iter()
        .map(|&k| {
            let p = surface.pos[k as usize];
            p - (p - ca).dot(nb) * nb
        })
        .collect();
    let pb: Vec<DVec3> = b.iter().map(|&k| surface.pos[k as usize]).collect();
    // cos of the angle between a diagonal and the axis; larger is straighter.
    let straightness = |from: DVec3, to: DVec3| {
        let d = to - from;
        d.dot(axis) / (d.length() * axis_len).max(1e-300)
    };
    let angle = |t: &[f64], k: usize| {
        let n = t.len();
        t[k % n] + std::f64::consts::TAU * (k / n) as f64
    };
    let (mut i, mut j) = (0usize, 0usize);
    while i < ma || j < mb {
        let advance_b = if i == ma {
            true
        } else if j == mb {
            false
        } else {
            let (na, nb_) = (angle(ta, i + 1), angle(tb, j + 1));
            let (step_a, step_b) = (na - angle(ta, i), nb_ - angle(tb, j));
            let b_allowed = nb_ <= na + 0.5 * step_a;
            let a_allowed = na <= nb_ + 0.5 * step_b;
            match (a_allowed, b_allowed) {
                (true, false) => false,
                (false, true) => true,
                _ => {
                    let via_b = straightness(pa[i % ma], pb[(j + 1) % mb]);
                    let via_a = straightness(pa[(i + 1) % ma], pb[j % mb]);
                    via_b > via_a || (via_b == via_a && nb_ < na)
                }
            }
        };
        if advance_b {
            surface.triangle(a[i % ma], b[(j + 1) % mb], b[j % mb]);
            j += 1;
        } else {
            surface.triangle(a[i % ma], a[(i + 1) % ma], b[j % mb]);
            i += 1;
        }
    }
}

/// Closes the tube after `ring` (if `forward`) or before it with a dome of
/// `rings` rings and an apex, inside the sphere of the ring's radius.
/// Returns the triangle range and the range of vertices it added.
pub fn cap(
    surface: &mut Surface,
    ring: &Ring,
    rings: u32,
    forward: bool,
) -> (std::ops::Range<u32>, std::ops::Range<u32>) {
    let t0 = surface.tris.len() as u32;
    let v0 = surface.pos.len() as u32;
    let dir = if forward { ring.normal } else { -ring.normal };
    let r = ring.radius;
    let mut prev = *ring;
    for k in 1..=rings {
        let phi = std::f64::consts::FRAC_PI_2 * f64::from(k) / f64::from(rings + 1);
        let center = ring.center + dir * (r * phi.sin());
        let first = surface.pos.len() as u32;
        for p in contour::ring(center, ring.normal, ring.u, r * phi.cos(), ring.m) {
            surface.vertex(p, ring.label);
        }
        let next = Ring {
            center,
            first,
            ..*ring
        };
        if forward {
            connect(surface, &prev, &next);
        } else {
            connect(surface, &next, &prev);
        }
        prev = next;
    }
    let apex = surface.vertex(ring.center + dir * r, ring.label);
    for j in 0..prev.m {
        let (a, b) = (prev.vertex(j), prev.vertex(j + 1));
        if forward {
            surface.triangle(a, b, apex);
        } else {
            surface.triangle(b, a, apex);
        }
    }
    (t0..surface.tris.len() as u32, v0..surface.pos.len() as u32)
}

/// Builds the rings and bands of one piece (list of kept track points) into the
/// surface, without caps.
pub fn build_piece(
    surface: &mut Surface,
    track: &Track,
    kept: &[usize],
    labels: &[u32],
    branch: u32,
) -> Tube {
    let mut rings: Vec<Ring> = Vec::with_capacity(kept.len());
    let mut bands = Vec::with_capacity(kept.len());
    for &i in kept {
        // Each kept contour's frame comes from the previous kept one, so skipped
        // contours leave no twist behind.
        let u = match rings.last() {
            Some(prev) => contour::push_forward(prev.u, prev.normal, track.samples[i].tangent),
            None => track.frames[i],
        };
        let ring = place_ring(surface, track, i, u, labels);
        if let Some(prev) = rings.last() {
            bands.push(surface.tris.len() as u32);
            connect(surface, prev, &ring);
        }
        rings.push(ring);
    }
    bands.push(surface.tris.len() as u32);
    let at = surface.tris.len() as u32;
    Tube {
        branch,
        rings,
        bands,
        start_cap: at..at,
        end_cap: at..at,
        start_cap_vertices: 0..0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::BuildStats;

    fn straight(n: usize, r: f64) -> Track {
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
        // Rebuild b with 12 vertices.
        s.pos.truncate(b.first as usize);
        s.label.truncate(b.first as usize);
        b.m = 12;
        for p in contour::ring(b.center, b.normal, b.u, b.radius, 12) {
            s.vertex(p, 1);
        }
        connect(&mut s, &a, &b);
        assert_eq!(s.tris.len(), 8 + 12);
    }

    #[test]
    fn capped_straight_tube_is_closed_and_outward() {
        let track = straight(5, 1.0);
        let (pieces, skipped) = select_contours(&track, 0);
        assert_eq!(pieces.len(), 1);
        assert_eq!(skipped, 0);
        let mut s = Surface::default();
        let labels: Vec<u32> = (0..5).collect();
        let tube = build_piece(&mut s, &track, &pieces[0], &labels, 0);
        cap(&mut s, &tube.rings[0], 3, false);
        cap(&mut s, tube.rings.last().unwrap(), 3, true);
        let mesh = s.into_mesh(BuildStats::default());
        let r = mesh.check();
        assert!(r.is_valid(), "{r}");
        assert_eq!(r.euler_characteristic, 2);
        // A cylinder of length 8 and radius 1 plus two hemispheres of radius ~1.
        let exact = std::f64::consts::PI * 8.0 + 4.0 / 3.0 * std::f64::consts::PI;
        assert!(
            (mesh.volume() - exact).abs() / exact < 0.03,
            "{}",
            mesh.volume()
        );
    }

    #[test]
    fn flat_caps_are_valid_too() {
        let track = straight(3, 0.5);
        let (pieces, _) = select_contours(&track, 0);
        let mut s = Surface::default();
        let tube = build_piece(&mut s, &track, &pieces[0], &[0, 1, 2], 0);
        cap(&mut s, &tube.rings[0], 0, false);
        cap(&mut s, tube.rings.last().unwrap(), 0, true);
        assert!(s.into_mesh(BuildStats::default()).check().is_valid());
    }

    #[test]
    fn hairpin_splits_into_pieces() {
        // Out along +x, a tight U-turn, back along −x next to itself.
        let mut pts: Vec<DVec3> = (0..10)
            .map(|i| DVec3::new(f64::from(i), 0.0, 0.0))
            .collect();
        pts.push(DVec3::new(9.5, 0.5, 0.0));
        pts.extend((0..10).map(|i| DVec3::new(9.0 - f64::from(i), 1.0, 0.0)));
        let track = Track::new(&pts, &vec![1.0; pts.len()], &Params::DEFAULT, None);
        let (pieces, skipped) = select_contours(&track, 0);
        assert!(pieces.len() >= 2, "{pieces:?}");
        assert!(skipped > 0);
        for piece in &pieces {
            for w in piece.windows(2) {
                assert!(track.disc(w[0]).clears(&track.disc(w[1]), 0.0));
            }
        }
    }
}
#[cfg(test)]
mod repro {
    use super::*;
    use crate::mesh::BuildStats;
    #[test]
    fn giant_radius_growth() {
        let pts = vec![
            DVec3::new(116.43106, 123.68894, 26.68),
            DVec3::new(116.49914, 123.97046, 26.68),
            DVec3::new(116.60678, 124.41758, 26.68),
            DVec3::new(116.71488, 124.86470, 26.68),
        ];
        let radii = vec![40.0, 692.1, 1728.4, 2764.7];
        let track = Track::new(&pts, &radii, &Params::DEFAULT, None);
        let (pieces, _) = select_contours(&track, 0);
        eprintln!("pieces {pieces:?} counts {:?}", track.counts);
        let mut s = Surface::default();
        for kept in &pieces {
            let t = build_piece(&mut s, &track, kept, &[0, 1, 2, 3], 0);
            eprintln!(
                "rings {:?}",
                t.rings.iter().map(|r| (r.first, r.m)).collect::<Vec<_>>()
            );
            cap(&mut s, &t.rings[0], 3, false);
            cap(&mut s, t.rings.last().unwrap(), 3, true);
        }
        let mesh = s.into_mesh(BuildStats::default());
        let r = mesh.check();
        eprintln!("{r}");
        eprintln!("pairs {:?}", r.intersecting_pairs);
        eprintln!("tube {:?}", pieces);
    }
}
