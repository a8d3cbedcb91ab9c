//! Branch tubes: contours connected into a surface, closed by tip caps
//! (paper §3.2, "Contour Connection").
//!
//! * **Connection.** Starting from the two first vertices (which correspond,
//!   thanks to the push-forward frames), each step adds one triangle, advancing
//!   on whichever contour comes next in angle about the axis P_iP_{i+1}: the
//!   paper's minimum included-angle rule, in a form that provably never folds a
//!   band (see [`connect_loops`]). The result has m_i + m_{i+1} triangles.
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
    /// Arc length along the resampled curve at each point.
    pub arc: Vec<f64>,
}

impl Track {
    /// Resamples and frames a branch given its points and radii.
    pub fn new(points: &[DVec3], radii: &[f64], params: &Params, u0: Option<DVec3>) -> Track {
        let r_avg = radii.iter().sum::<f64>() / radii.len() as f64;
        let edge = r_avg / params.resolution;
        let mut samples = spline::resample(points, radii, edge, params.k1);
        spline::smooth_tangents(&mut samples);
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
        let mut arc = Vec::with_capacity(samples.len());
        let mut acc = 0.0;
        for (i, s) in samples.iter().enumerate() {
            if i > 0 {
                acc += s.pos.distance(samples[i - 1].pos);
            }
            arc.push(acc);
        }
        Track {
            samples,
            frames,
            counts,
            radii,
            edge,
            arc,
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

/// Whether the contour of point `k` may follow the kept contour of point `j`:
/// the two discs clear each other (the paper's intersection rule) and the band
/// between them is a sound frustum, its axis within 60° of both normals. The
/// second condition rejects contours that clear `j` only because the skeleton
/// jogged sideways in between; a band across such a jog would cut the corner
/// and be nearly edge-on to its own axis.
pub fn may_follow(track: &Track, j: usize, k: usize) -> bool {
    if !track.disc(j).clears(&track.disc(k), track.margin(j, k)) {
        return false;
    }
    let d = (track.samples[k].pos - track.samples[j].pos).normalize_or_zero();
    d.dot(track.samples[j].tangent) >= 0.5 && d.dot(track.samples[k].tangent) >= 0.5
}

/// Chooses which contours to keep, in pieces. Each piece is a list of point
/// indices in which each contour may follow the previous one ([`may_follow`]);
/// skipped contours leave no hole because the next kept one is connected to the
/// last. A piece ends, and the rest of the branch starts a new piece (to be
/// spliced onto the first like a secondary branch), when
///
/// * no contour within a few radii of path can follow (a hairpin tighter than
///   the tube, a spike in the trace), or
/// * the next band would reach an earlier, non-adjacent band of the same piece
///   (the branch curls back onto itself closer than its radius).
///
/// `first` is the first point to consider (earlier ones are inside something
/// else). Also returns how many contours were skipped.
pub fn select_contours(track: &Track, first: usize) -> (Vec<Vec<usize>>, u32) {
    let n = track.samples.len();
    let mut pieces = Vec::new();
    let mut skipped = 0u32;
    let mut start = first.min(n - 1);
    loop {
        let mut kept = vec![start];
        let mut split_at = None;
        let mut bands = BandIndex::new(track);
        for k in start + 1..n {
            let j = kept[kept.len() - 1];
            if may_follow(track, j, k) {
                if bands.reaches_back(track, j, k) {
                    split_at = Some(k);
                    break;
                }
                bands.insert(track, j, k);
                kept.push(k);
                continue;
            }
            skipped += 1;
            let reach =
                4.0 * track.samples[j].radius.max(track.samples[k].radius) + 2.0 * track.edge;
            if track.arc[k] - track.arc[j] > reach {
                split_at = Some(k);
                break;
            }
        }
        let last = kept[kept.len() - 1];
        pieces.push(kept);
        match split_at {
            // Split only when the rest of the branch is worth a piece of its own.
            Some(k) if track.arc[n - 1] - track.arc[k] > track.samples[last].radius => start = k,
            _ => break,
        }
    }
    (pieces, skipped)
}

/// The bands kept so far in a piece, as capsules in a uniform grid, to find a
/// new band that runs into an earlier one.
struct BandIndex {
    cell: f64,
    grid: std::collections::HashMap<[i64; 3], Vec<usize>>,
    /// (from point, to point, radius) of each band.
    capsules: Vec<(usize, usize, f64)>,
}

impl BandIndex {
    fn new(track: &Track) -> BandIndex {
        let rmax = track.radii.iter().copied().fold(0.0, f64::max);
        BandIndex {
            cell: (4.0 * rmax).max(4.0 * track.edge).max(1e-300),
            grid: std::collections::HashMap::new(),
            capsules: Vec::new(),
        }
    }

    fn cells(&self, a: DVec3, b: DVec3, pad: f64) -> impl Iterator<Item = [i64; 3]> {
        let lo = ((a.min(b) - DVec3::splat(pad)) / self.cell).floor();
        let hi = ((a.max(b) + DVec3::splat(pad)) / self.cell).floor();
        let (lo, hi) = (lo.as_i64vec3(), hi.as_i64vec3());
        (lo.x..=hi.x).flat_map(move |x| {
            (lo.y..=hi.y).flat_map(move |y| (lo.z..=hi.z).map(move |z| [x, y, z]))
        })
    }

    fn insert(&mut self, track: &Track, j: usize, k: usize) {
        let r = track.radii[j].max(track.radii[k]);
        let id = self.capsules.len();
        self.capsules.push((j, k, r));
        let (a, b) = (track.samples[j].pos, track.samples[k].pos);
        let cells: Vec<[i64; 3]> = self.cells(a, b, 0.0).collect();
        for c in cells {
            self.grid.entry(c).or_default().push(id);
        }
    }

    /// Whether band (j, k) comes within reach of an earlier band whose end is
    /// more than two radii sums of path behind `j`.
    fn reaches_back(&self, track: &Track, j: usize, k: usize) -> bool {
        let (a, b) = (track.samples[j].pos, track.samples[k].pos);
        let r = track.radii[j].max(track.radii[k]);
        let mut seen = std::collections::HashSet::new();
        for c in self.cells(a, b, self.cell) {
            let Some(ids) = self.grid.get(&c) else {
                continue;
            };
            for &id in ids {
                if !seen.insert(id) {
                    continue;
                }
                let (p, q, rq) = self.capsules[id];
                if track.arc[j] - track.arc[q] <= 2.0 * (r + rq) {
                    continue; // a neighbour along the tube
                }
                let d = segment_distance(a, b, track.samples[p].pos, track.samples[q].pos);
                if d < r + rq {
                    return true;
                }
            }
        }
        false
    }
}

/// Distance between the segments (a, b) and (c, d).
pub fn segment_distance(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    let (u, v, w) = (b - a, d - c, a - c);
    let (aa, bb, cc, dd, ee) = (u.dot(u), u.dot(v), v.dot(v), u.dot(w), v.dot(w));
    let den = aa * cc - bb * bb;
    let (mut s, mut t);
    if aa <= 1e-300 && cc <= 1e-300 {
        return a.distance(c);
    }
    if aa <= 1e-300 {
        s = 0.0;
        t = (ee / cc).clamp(0.0, 1.0);
    } else if cc <= 1e-300 {
        t = 0.0;
        s = (-dd / aa).clamp(0.0, 1.0);
    } else {
        s = if den > 1e-12 * aa * cc {
            ((bb * ee - cc * dd) / den).clamp(0.0, 1.0)
        } else {
            0.0
        };
        t = (bb * s + ee) / cc;
        if t < 0.0 {
            t = 0.0;
            s = (-dd / aa).clamp(0.0, 1.0);
        } else if t > 1.0 {
            t = 1.0;
            s = ((bb - dd) / aa).clamp(0.0, 1.0);
        }
    }
    (a + u * s).distance(c + v * t)
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

/// Connects ring `a` (behind) to ring `b` (in front).
pub fn connect(surface: &mut Surface, a: &Ring, b: &Ring) {
    connect_loops(surface, &ring_loop(a), &ring_loop(b), a.center, b.center);
}

/// The vertex indices of a ring in order.
pub fn ring_loop(r: &Ring) -> Vec<u32> {
    (0..r.m).map(|j| r.first + j).collect()
}

/// Connects two vertex loops that both wind once, counter-clockwise, about the
/// axis from `ca` (centre of `a`, behind) to `cb` (centre of `b`, in front).
///
/// This is the paper's contour connection with its criterion made robust. The
/// paper projects C_i onto a plane parallel to C_{i+1}, starts from the first
/// vertices and adds, step by step, the triangle whose new diagonal makes the
/// smaller angle with P_iP_{i+1}. We project both loops along the axis P_iP_{i+1}
/// itself and take the vertex that comes next in angle about the axis. For
/// similar parallel contours the two rules pick the same triangles; at sharp
/// turns (strongly tilted contours close together) the literal rule can let
/// diagonals cross and fold the band, while the angular order cannot: along any
/// segment that misses the axis the angle about it is monotonic, so each triangle
/// occupies its own angular sector, and only triangles that share an edge meet.
/// The start is `a`'s first vertex and the vertex of `b` nearest to it in angle
/// (the corresponding first vertex, for push-forward contours).
pub fn connect_loops(surface: &mut Surface, a: &[u32], b: &[u32], ca: DVec3, cb: DVec3) {
    let (ma, mb) = (a.len(), b.len());
    let d = (cb - ca).normalize_or_zero();
    let d = if d == DVec3::ZERO { DVec3::Z } else { d };
    let e1 = contour::any_perpendicular(d);
    let e2 = d.cross(e1);
    let angle_of = |k: u32, c: DVec3| {
        let p = surface.pos[k as usize] - c;
        p.dot(e2).atan2(p.dot(e1))
    };
    let tau = std::f64::consts::TAU;
    // Unwrapped angles, increasing from the loop's start.
    let unwrap = |raw: Vec<f64>, from: f64| -> Vec<f64> {
        raw.iter()
            .map(|&t| from + (t - from).rem_euclid(tau))
            .collect()
    };
    let a_raw: Vec<f64> = a.iter().map(|&k| angle_of(k, ca)).collect();
    let ta = unwrap(a_raw, angle_of(a[0], ca));
    let b_raw: Vec<f64> = b.iter().map(|&k| angle_of(k, cb)).collect();
    // Start of b: the vertex nearest in angle to a's first vertex.
    let start_b = (0..mb)
        .min_by(|&x, &y| {
            let dx =
                (b_raw[x] - ta[0] + std::f64::consts::PI).rem_euclid(tau) - std::f64::consts::PI;
            let dy =
                (b_raw[y] - ta[0] + std::f64::consts::PI).rem_euclid(tau) - std::f64::consts::PI;
            dx.abs().total_cmp(&dy.abs())
        })
        .unwrap_or(0);
    let b0 = ta[0]
        + ((b_raw[start_b] - ta[0] + std::f64::consts::PI).rem_euclid(tau) - std::f64::consts::PI);
    let rotated: Vec<f64> = (0..mb).map(|k| b_raw[(start_b + k) % mb]).collect();
    let tb = unwrap(rotated, b0);
    let monotone = |t: &[f64]| t.windows(2).all(|w| w[1] > w[0]);
    // Rings always wind monotonically; for anything else fall back to even spacing.
    let (ta, tb) = if monotone(&ta) && monotone(&tb) {
        (ta, tb)
    } else {
        (
            (0..ma).map(|k| tau * k as f64 / ma as f64).collect(),
            (0..mb).map(|k| tau * k as f64 / mb as f64).collect(),
        )
    };
    let next = |t: &[f64], k: usize| if k < t.len() { t[k] } else { t[0] + tau };
    let bv = |j: usize| b[(start_b + j) % mb];
    let (mut i, mut j) = (0usize, 0usize);
    while i < ma || j < mb {
        let advance_b = if i == ma {
            true
        } else if j == mb {
            false
        } else {
            next(&tb, j + 1) < next(&ta, i + 1)
        };
        if advance_b {
            surface.triangle(a[i % ma], bv(j + 1), bv(j));
            j += 1;
        } else {
            surface.triangle(a[i % ma], a[(i + 1) % ma], bv(j));
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
    // The dome's meridian is a polygon of 4·(rings + 1) sides inscribed in a
    // quarter circle; enlarge it like the contours (see `polygon_radius`) so the
    // cap's area and volume errors stay balanced too.
    let r = contour::polygon_radius(ring.radius, 4 * (rings + 1));
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
        assert_eq!(s.tris.len(), a.m as usize + 12);
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
    fn segment_distances() {
        let d = segment_distance(
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(0.5, 1.0, 0.0),
            DVec3::new(0.5, 2.0, 0.0),
        );
        assert!((d - 1.0).abs() < 1e-12);
        let d = segment_distance(
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(2.0, 1.0, 0.0),
            DVec3::new(3.0, 1.0, 0.0),
        );
        assert!((d - 2f64.sqrt()).abs() < 1e-12);
        let d = segment_distance(
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(0.5, -1.0, 1.0),
            DVec3::new(0.5, 1.0, 1.0),
        );
        assert!((d - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_loop_closing_on_itself_splits() {
        // A full circle of radius 3 with a tube of radius 1: the end runs into the start.
        let pts: Vec<DVec3> = (0..=40)
            .map(|i| {
                let t = f64::from(i) / 40.0 * std::f64::consts::TAU * 1.1;
                DVec3::new(3.0 * t.cos(), 3.0 * t.sin(), 0.0)
            })
            .collect();
        let track = Track::new(&pts, &vec![1.0; pts.len()], &Params::DEFAULT, None);
        let (pieces, _) = select_contours(&track, 0);
        assert!(pieces.len() >= 2, "{pieces:?}");
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
