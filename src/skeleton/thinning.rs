//! Contours that a straight stretch of a track does not need.
//!
//! Formula (1) puts a contour about every average radius along a branch
//! whatever its shape, and for a bend it must. Along a stretch whose centre
//! runs straight and whose polygon radius changes linearly, though, the band
//! between two contours a few radii apart is the same surface as the bands
//! through the contours between them, to within a small share of the radius.
//! Those contours only add triangles, and every later stage (splicing, the
//! overlap pass, writing) pays for each one: leaving them out halves the
//! triangles of a typical cell without moving its area or volume.
//!
//! A contour is left out only where all of this holds:
//! - its point was inserted by the resampler: an original point of the trace
//!   always keeps its contour (the branch's points, the branch points its
//!   children grow from, and the track's mapping of them stay as they were);
//! - it lies more than [`END_REACH`] radii from both ends of the track and
//!   is not among its [`END_POINTS`] first or last points: a child's junction
//!   is built from its first contours outside its parent, a tip's dome on its
//!   last, and both need the contours the trace has there;
//! - it has the vertex count of the contour the stretch starts from;
//! - its centre and polygon radius lie within [`TOLERANCE`] of its radius of
//!   the straight line and the linear radius between the ends;
//! - the stretch is at most [`LONGEST`] times the smaller end radius long,
//!   so its triangles stay short next to the cell's features.
//!
//! The mesher thins the tracks of branch tubes other than trunks (see
//! [`crate::skeleton::tracks`]); the straight cones of fillers keep their
//! dense contours, which follow the hull of a thick sphere and a thin one.
//!
//! This departs from formula (1), which has no notion of straightness. A
//! 12-gon's own edges lie 3.4 % of the radius inside the circle, so a
//! tolerance of 1 % keeps the surface as close to the skeleton's cones as
//! the contours themselves are.

use crate::skeleton::spline::Sample;

/// Largest distance, as a share of a point's radius, between the contour
/// left out and the band that replaces it.
pub const TOLERANCE: f64 = 0.01;

/// Longest stretch between two kept contours, in units of the smaller of
/// their radii.
pub const LONGEST: f64 = 4.0;

/// Points at each end of a track that always keep their contours.
pub const END_POINTS: usize = 2;

/// Reach around each end of a track, in radii (the widest from the start:
/// a branch starts at its parent's radius), inside which every contour is
/// kept: where a child leaves its parent the junction picks its first contour
/// outside the parent and splices it, and a tip's dome sits on its last.
pub const END_REACH: f64 = 3.0;

/// Whether each point keeps its contour: a greedy walk from the first point
/// that stretches each band over as many following points as it can.
pub fn needed(samples: &[Sample], radii: &[f64], counts: &[u32]) -> Vec<bool> {
    let n = samples.len();
    let mut keep = vec![true; n];
    if n < 3 {
        return keep;
    }
    // The widest radius from the start up to each point.
    let mut widest = Vec::with_capacity(n);
    let mut w: f64 = 0.0;
    for s in samples {
        w = w.max(s.radius);
        widest.push(w);
    }
    let (first, last) = (samples[0].pos, samples[n - 1].pos);
    let near_ends = |i: usize| {
        first.distance(samples[i].pos) <= END_REACH * widest[i]
            || last.distance(samples[i].pos)
                <= END_REACH * samples[i].radius.max(samples[n - 1].radius)
    };
    let droppable = |i: usize| {
        !samples[i].original
            && i >= END_POINTS
            && i + END_POINTS < n
            && counts[i] == counts[i - 1]
            && !near_ends(i)
    };
    let mut a = 0;
    while a + 1 < n {
        // Extend the stretch a..=e while every point strictly inside it may go.
        let mut e = a + 1;
        while e + 1 < n && droppable(e) && spans(samples, radii, a, e + 1) {
            keep[e] = false;
            e += 1;
        }
        a = e;
    }
    keep
}

/// Whether the band from point `a` to point `e` stands for every point
/// between them (see the module docs).
fn spans(samples: &[Sample], radii: &[f64], a: usize, e: usize) -> bool {
    let (pa, pe) = (samples[a].pos, samples[e].pos);
    let axis = pe - pa;
    let len2 = axis.length_squared();
    if len2 <= 0.0 || len2.sqrt() > LONGEST * radii[a].min(radii[e]) {
        return false;
    }
    (a + 1..e).all(|i| {
        let u = ((samples[i].pos - pa).dot(axis) / len2).clamp(0.0, 1.0);
        let centre = pa + axis * u;
        let radius = radii[a] + (radii[e] - radii[a]) * u;
        samples[i].pos.distance(centre) + (radii[i] - radius).abs() <= TOLERANCE * radii[i]
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    fn sample(x: f64, y: f64, original: bool) -> Sample {
        Sample {
            pos: DVec3::new(x, y, 0.0),
            tangent: DVec3::X,
            radius: 1.0,
            source: 0,
            original,
        }
    }

    #[test]
    fn a_straight_stretch_keeps_a_contour_every_few_radii() {
        let s: Vec<Sample> = (0..41)
            .map(|i| sample(0.5 * f64::from(i), 0.0, i % 20 == 0))
            .collect();
        let keep = needed(&s, &vec![1.0; s.len()], &vec![12; s.len()]);
        let kept: Vec<usize> = (0..s.len()).filter(|&i| keep[i]).collect();
        // Everything within 3 radii of the ends, the original points, and
        // one contour at most 4 radii on.
        for must in (0..=6).chain([20]).chain(34..=40) {
            assert!(keep[must], "{must} in {kept:?}");
        }
        assert!(
            kept.windows(2)
                .all(|w| s[w[1]].pos.x - s[w[0]].pos.x <= 4.0 + 1e-9)
        );
        assert!(kept.len() < 20, "{kept:?}");
    }

    #[test]
    fn a_bend_a_radius_change_or_a_count_change_keeps_every_contour() {
        let n = 30;
        let bent: Vec<Sample> = (0..n)
            .map(|i| {
                let t = 0.15 * f64::from(i as u32);
                sample(3.0 * t.sin(), 3.0 * (1.0 - t.cos()), false)
            })
            .collect();
        let keep = needed(&bent, &vec![1.0; n], &vec![12; n]);
        assert!(keep.iter().all(|&k| k), "{keep:?}");
        let straight: Vec<Sample> = (0..n).map(|i| sample(0.5 * i as f64, 0.0, false)).collect();
        // A radius that bulges in the middle of each pair of points.
        let radii: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { 1.0 } else { 1.1 }).collect();
        assert!(needed(&straight, &radii, &vec![12; n]).iter().all(|&k| k));
        let counts: Vec<u32> = (0..n).map(|i| if i % 2 == 0 { 12 } else { 14 }).collect();
        assert!(needed(&straight, &vec![1.0; n], &counts).iter().all(|&k| k));
    }

    #[test]
    fn a_linear_taper_is_thinned() {
        let n = 40;
        let s: Vec<Sample> = (0..n).map(|i| sample(0.5 * i as f64, 0.0, false)).collect();
        let radii: Vec<f64> = (0..n).map(|i| 2.0 - 0.02 * i as f64).collect();
        let keep = needed(&s, &radii, &vec![12; n]);
        assert!(keep.iter().filter(|&&k| k).count() < n / 2, "{keep:?}");
    }
}
