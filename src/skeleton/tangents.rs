//! Contour orientation: each tangent turned into the direction of the curve
//! over one radius either side, the scale at which a disc of that radius
//! sees the skeleton, widened where neighbouring discs would cross.

use glam::DVec3;

use super::frame::DiscFrame;
use super::spline::Sample;

/// Replaces each tangent by the direction of the curve at the scale of the tube:
/// the chord from the point `h` back to the point `h` ahead along the
/// resampled curve (one-sided at the ends), where `h` is the point's radius,
/// or a multiple of it where the contours would cross at that scale.
///
/// A contour is a disc of radius r, so its orientation should follow the
/// skeleton at the scale r. Tracing jitter (points closer together than the
/// radius, wiggling by tens of degrees) otherwise tilts neighbouring discs into
/// each other, and every such contour would have to be skipped. Where the
/// skeleton bends on a scale larger than r (the common case) the chord is the
/// spline's derivative to first order.
///
/// Where the skeleton turns sharply within a few radii (a voxel trace's
/// staircase: right-angle steps 2.8 radii long), discs oriented at the scale
/// r still turn faster than they advance and cross each other; the paper's
/// rule then skips them, and the band from the last kept contour to the next
/// cuts whole steps off, a few per cent of the cell's volume. There the
/// scale is widened ([`TURN_SCALES`]) over [`TURN_REACH`] radii around each
/// pair of neighbouring discs that would cross, until they clear: the
/// contours then follow the staircase's overall course, and
/// [`crate::skeleton::track`]'s sweep widening gives back the length they no longer
/// follow. Only between original segments at least [`TURN_SEGMENT`] radii
/// long: shorter ones are jitter, which the scale r already smooths, and
/// skipping a contour there costs little (see [`TURN_SEGMENT`]).
pub fn smooth_tangents(samples: &mut [Sample]) {
    smooth_tangents_at(samples, &TURN_SCALES);
}

/// [`smooth_tangents`] with the scales given (the tests compare the paper's
/// single scale with the widened ones).
fn smooth_tangents_at(samples: &mut [Sample], scales: &[f64]) {
    let n = samples.len();
    if n < 2 {
        return;
    }
    let mut arc = Vec::with_capacity(n);
    let mut acc = 0.0;
    arc.push(0.0);
    for w in samples.windows(2) {
        acc += w[0].pos.distance(w[1].pos);
        arc.push(acc);
    }
    let total = acc;
    let at = |s: f64| -> DVec3 {
        let k = arc.partition_point(|&a| a < s).clamp(1, n - 1);
        let (a0, a1) = (arc[k - 1], arc[k]);
        let t = if a1 > a0 {
            ((s - a0) / (a1 - a0)).clamp(0.0, 1.0)
        } else {
            1.0
        };
        samples[k - 1].pos.lerp(samples[k].pos, t)
    };
    let spline: Vec<DVec3> = samples.iter().map(|s| s.tangent).collect();
    let tangent = |i: usize, scale: f64| -> DVec3 {
        let h = samples[i].radius * scale;
        let chord = at((arc[i] + h).min(total)) - at((arc[i] - h).max(0.0));
        let len = chord.length();
        if len > 1e-9 * h.max(1e-300) {
            chord / len
        } else {
            spline[i]
        }
    };
    // Each point's original segment length (an original point: the longer
    // of its two).
    let originals: Vec<usize> = (0..n)
        .filter(|&i| samples[i].original || i == n - 1)
        .collect();
    let mut segment = vec![0.0f64; n];
    for w in originals.windows(2) {
        let len = arc[w[1]] - arc[w[0]];
        for l in &mut segment[w[0]..=w[1]] {
            *l = l.max(len);
        }
    }
    let mut level = vec![0usize; n];
    let mut tangents: Vec<DVec3> = (0..n).map(|i| tangent(i, scales[0])).collect();
    // The points raised in a pass (once each per raise; their tangents are
    // recomputed after it, the others kept).
    let mut raised: Vec<usize> = Vec::new();
    for _ in 1..scales.len() {
        raised.clear();
        let mut i = 0;
        while i + 1 < n {
            let (a, b) = (&samples[i], &samples[i + 1]);
            if segment[i].min(segment[i + 1]) < TURN_SEGMENT * a.radius.max(b.radius)
                || turn_discs_clear(a, tangents[i], b, tangents[i + 1])
            {
                i += 1;
                continue;
            }
            let reach = TURN_REACH * a.radius.max(b.radius);
            let lo = arc.partition_point(|&s| s < arc[i] - reach);
            let hi = arc.partition_point(|&s| s <= arc[i + 1] + reach);
            for (k, l) in level.iter_mut().enumerate().take(hi).skip(lo) {
                if *l + 1 < scales.len() {
                    *l += 1;
                    raised.push(k);
                }
            }
            i = hi.max(i + 1);
        }
        if raised.is_empty() {
            break;
        }
        for &k in &raised {
            tangents[k] = tangent(k, scales[level[k]]);
        }
    }
    for (s, t) in samples.iter_mut().zip(tangents) {
        s.tangent = t;
    }
}

/// Whether the discs [`smooth_tangents`] tests at neighbouring samples `a`
/// and `b` (oriented along `ta` and `tb`) clear each other.
fn turn_discs_clear(a: &Sample, ta: DVec3, b: &Sample, tb: DVec3) -> bool {
    let disc = |s: &Sample, t: DVec3| DiscFrame {
        center: s.pos,
        normal: t,
        radius: TURN_DISC * s.radius,
    };
    disc(a, ta).clears(&disc(b, tb), 0.02 * a.radius.min(b.radius))
}

/// The scales, in radii, at which [`smooth_tangents`] orients contours: the
/// first everywhere, the next where neighbouring discs would cross at the
/// one before.
pub const TURN_SCALES: [f64; 3] = [1.0, 1.5, 2.0];

/// How far either side of two crossing discs, in radii, [`smooth_tangents`]
/// widens the scale.
pub const TURN_REACH: f64 = 2.0;

/// [`smooth_tangents`] widens the scale only where both crossing discs lie on
/// original segments at least this many radii long (a diameter). Shorter
/// segments are jitter (electron-microscopy traces), which the scale r
/// already smooths: widened there too, their tubes lose the skipping that
/// keeps them smooth and stand out of the union of round cones.
pub const TURN_SEGMENT: f64 = 2.0;

/// The discs [`smooth_tangents`] tests are this much wider than the
/// skeleton's radius: the contour's polygon is a few percent wider
/// ([`crate::skeleton::contour::polygon_radius`]).
const TURN_DISC: f64 = 1.05;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skeleton::spline::resample;

    /// Pairs of neighbouring samples whose discs (as `smooth_tangents`
    /// tests them) cross.
    fn crossing_pairs(s: &[Sample]) -> usize {
        s.windows(2)
            .filter(|w| !turn_discs_clear(&w[0], w[0].tangent, &w[1], w[1].tangent))
            .count()
    }

    /// Resampled as a track does (edge = mean radius), tangents at the
    /// scales given.
    fn oriented(pts: &[DVec3], r: f64, scales: &[f64]) -> Vec<Sample> {
        let mut s = resample(pts, &vec![r; pts.len()], r, 1);
        smooth_tangents_at(&mut s, scales);
        s
    }

    #[test]
    fn a_voxel_staircase_widens_the_scale_until_the_discs_clear() {
        // Right-angle steps 2.83 radii long (a voxel trace's, radius 0.235):
        // at the scale r the discs cross at every corner.
        let (step, r) = (0.665, 0.235);
        let pts: Vec<DVec3> = (0..40)
            .map(|k| {
                let (x, y) = ((k + 1) / 2, k / 2);
                DVec3::new(step * f64::from(x), step * f64::from(y), 0.0)
            })
            .collect();
        // (76 of 157 pairs cross at the scale r; none once widened.)
        let at_r = crossing_pairs(&oriented(&pts, r, &[1.0]));
        assert!(at_r >= 38, "the test needs crossing discs: {at_r}");
        let widened = oriented(&pts, r, &TURN_SCALES);
        assert_eq!(crossing_pairs(&widened), 0, "of {at_r} at the scale r");
        for x in &widened {
            assert!((x.tangent.length() - 1.0).abs() < 1e-9, "{x:?}");
        }
    }

    #[test]
    fn jitter_shorter_than_a_diameter_keeps_the_scale_of_the_radius() {
        // Segments of 1.2 radii zigzagging ±60° about x: discs cross at the
        // scale r, but the segments are jitter and the scale stays r.
        let r = 0.5;
        let pts: Vec<DVec3> = (0..40)
            .map(|k| {
                let y = if k % 2 == 0 { 0.0 } else { 0.52 };
                DVec3::new(0.3 * f64::from(k), y, 0.0)
            })
            .collect();
        let at_r = oriented(&pts, r, &[1.0]);
        assert!(crossing_pairs(&at_r) > 0, "the test needs crossing discs");
        assert_eq!(oriented(&pts, r, &TURN_SCALES), at_r);
    }
}
