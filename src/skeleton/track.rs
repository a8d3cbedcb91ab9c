//! A branch ready for contours: resampled, framed and sized (formulas 1–3).
//!
//! [`Track::new`] resamples the branch's points (see [`crate::skeleton::spline`]), turns
//! the tangents into radius-scale directions, pushes the first-vertex frame
//! forward and computes each point's vertex count and polygon radius (see
//! [`crate::skeleton::contour`]), widened where the trace jitters below the radius
//! scale (see [`SWEEP_CAP`]). [`may_follow`] is the rule for which contour
//! may follow which: the paper's "skip intersecting contours" plus a sanity
//! check on the band's shape.

use glam::DVec3;

use crate::params::Params;
use crate::skeleton::contour;
use crate::skeleton::frame::DiscFrame;
use crate::skeleton::spline::{self, Sample};

/// The resampled, framed points of a branch with their contour sizes.
#[derive(Debug, Clone, Default)]
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
    /// For each of the branch's original points, its resampled point (a
    /// merged near-duplicate maps to the point it was merged into).
    pub originals: Vec<usize>,
}

impl Track {
    /// Resamples and frames a branch given its points and radii.
    pub fn new(points: &[DVec3], radii: &[f64], params: &Params, u0: Option<DVec3>) -> Track {
        Track::widened_from(points, radii, params, u0, 0, SWEEP_CAP)
    }

    /// [`Track::new`], its contours widened where the trace jitters (see
    /// [`SWEEP_CAP`]) by at most `cap`, and only from the original point
    /// `first` on: a trunk's first segment runs from the soma's centre with
    /// the soma's radius, where the skeleton's bends are the soma's and the
    /// radius-scale tangents turn against the travel.
    pub fn widened_from(
        points: &[DVec3],
        radii: &[f64],
        params: &Params,
        u0: Option<DVec3>,
        first: usize,
        cap: f64,
    ) -> Track {
        let r_avg = radii.iter().sum::<f64>() / radii.len() as f64;
        let edge = r_avg / params.resolution;
        let mut samples = spline::resample(points, radii, edge, params.k1);
        super::tangents::smooth_tangents(&mut samples);
        spline::reach_of_spheres(&mut samples, points, radii);
        let start_u = u0
            .map(|u| u - u.dot(samples[0].tangent) * samples[0].tangent)
            .filter(|u| u.length_squared() > 1e-12)
            .map_or_else(
                || crate::kernel::vector::any_perpendicular(samples[0].tangent),
                DVec3::normalize,
            );
        let frames = crate::skeleton::frame::frames(samples.iter().map(|s| s.tangent), start_u);
        let counts: Vec<u32> = samples
            .iter()
            .map(|s| {
                contour::vertex_count(s.radius, edge, params.min_vertices, params.max_vertices)
            })
            .collect();
        let mut arc = Vec::with_capacity(samples.len());
        let mut acc = 0.0;
        for (i, s) in samples.iter().enumerate() {
            if i > 0 {
                acc += s.pos.distance(samples[i - 1].pos);
            }
            arc.push(acc);
        }
        let from = samples
            .iter()
            .position(|s| s.source as usize >= first)
            .unwrap_or(samples.len());
        let radii = samples
            .iter()
            .zip(&counts)
            .zip(sweep_factors(&samples, &arc, from, cap))
            .map(|((s, &m), f)| contour::polygon_radius(s.radius, m) * f)
            .collect();
        let originals = originals_of(&samples, points.len());
        Track {
            samples,
            frames,
            counts,
            radii,
            edge,
            arc,
            originals,
        }
    }

    /// The track without the contours its straight stretches do not need
    /// (see [`crate::skeleton::thinning`]): a branch's tube is built from this; the
    /// straight cones of fillers keep their dense contours.
    #[must_use]
    pub fn thinned(self) -> Track {
        let keep = crate::skeleton::thinning::needed(&self.samples, &self.radii, &self.counts);
        if keep.iter().all(|&k| k) {
            return self;
        }
        let mut t = self;
        keep_only(&mut t.samples, &keep);
        keep_only(&mut t.frames, &keep);
        keep_only(&mut t.counts, &keep);
        keep_only(&mut t.radii, &keep);
        keep_only(&mut t.arc, &keep);
        // Without the room of the points dropped, which on a large tree is
        // a third more than the points kept.
        t.samples.shrink_to_fit();
        t.frames.shrink_to_fit();
        t.counts.shrink_to_fit();
        t.radii.shrink_to_fit();
        t.arc.shrink_to_fit();
        // Original points always keep their contours: map them again.
        t.originals = originals_of(&t.samples, t.originals.len());
        t
    }

    /// How much point `i`'s contour was widened where the trace jitters.
    pub fn widening(&self, i: usize) -> f64 {
        self.radii[i] / contour::polygon_radius(self.samples[i].radius, self.counts[i])
    }

    /// The most any of the track's contours was widened (1 where none was).
    pub fn widest(&self) -> f64 {
        (0..self.samples.len())
            .map(|i| self.widening(i))
            .fold(1.0, f64::max)
    }

    /// The track cut to its first `end` points (at least one).
    pub fn prefix(&self, end: usize) -> Track {
        let end = end.clamp(1, self.samples.len());
        Track {
            samples: self.samples[..end].to_vec(),
            frames: self.frames[..end].to_vec(),
            counts: self.counts[..end].to_vec(),
            radii: self.radii[..end].to_vec(),
            edge: self.edge,
            arc: self.arc[..end].to_vec(),
            originals: self.originals.iter().map(|&k| k.min(end - 1)).collect(),
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

/// Most a contour's radius is widened where the trace jitters below the
/// radius scale: the tube's bands sweep the length along their smoothed
/// normals, the round cones the jittering length, and the radius grows by
/// the square root of their ratio over a radius either side, up to this
/// cap. The cap is wide enough for electron-microscopy traces that jitter
/// below their radius; wider tubes crowd the fillers on thick trunks,
/// though, so a cell whose first union leaves crossings is built again at
/// [`SAFE_SWEEP_CAP`] (`pipeline::unite`).
pub const SWEEP_CAP: f64 = 1.25;

/// The widening cap of the second construction, for cells whose first
/// leaves crossings at [`SWEEP_CAP`]: narrower tubes leave the fillers on a
/// thick trunk room to unite.
pub const SAFE_SWEEP_CAP: f64 = 1.15;

/// Per point, how much wider its contour must be for the tube to sweep the
/// volume its own stretch of skeleton does. A band between two contours
/// holds about πr² times the distance between them *along the contour
/// normals*; the normals follow the curve smoothed over a radius
/// ([`super::tangents::smooth_tangents`]), so where the trace jitters at a smaller
/// scale the tube covers only the smoothed length, while the round cones
/// cover the jittering one. Over a window of a radius either side, the
/// ratio of the two lengths is made up by the cross-section: the radius
/// grows by its square root (at most `cap`).
fn sweep_factors(samples: &[Sample], arc: &[f64], from: usize, cap: f64) -> Vec<f64> {
    let n = samples.len();
    // Running sums over the bands (band k joins points k and k + 1) of their
    // length along the mean of their normals, so that each point's window
    // costs two binary searches, not a walk: on a blob cell a radius spans
    // the whole branch.
    let mut swept_to = Vec::with_capacity(n);
    swept_to.push(0.0);
    for i in 1..n {
        let d = samples[i].pos - samples[i - 1].pos;
        let t = (samples[i].tangent + samples[i - 1].tangent).normalize_or_zero();
        swept_to.push(swept_to[i - 1] + d.dot(t).max(0.0));
    }
    (0..n)
        .map(|i| {
            if i < from {
                return 1.0;
            }
            // The bands from point lo to point hi, lo ≤ i ≤ hi (arc rises).
            let w = samples[i].radius;
            let lo = arc.partition_point(|&a| a < arc[i] - w).max(from);
            let hi = arc.partition_point(|&a| a <= arc[i] + w).saturating_sub(1);
            let length = arc[hi] - arc[lo];
            let swept = swept_to[hi] - swept_to[lo];
            if length <= 0.0 || swept <= 0.0 {
                return 1.0;
            }
            (length / swept).sqrt().clamp(1.0, cap)
        })
        .collect()
}

/// For each of `n` original points, its resampled point in `samples`.
fn originals_of(samples: &[Sample], n: usize) -> Vec<usize> {
    let mut originals = vec![0usize; n];
    for (i, s) in samples.iter().enumerate() {
        if s.original {
            originals[s.source as usize] = i;
        }
    }
    // Points merged into their predecessor take its resampled index.
    for k in 1..originals.len() {
        if originals[k] < originals[k - 1] {
            originals[k] = originals[k - 1];
        }
    }
    originals
}

/// Keeps the items of `v` whose flag in `keep` is set (`Vec::retain` visits
/// them in order, once each).
fn keep_only<T>(v: &mut Vec<T>, keep: &[bool]) {
    let mut flags = keep.iter();
    v.retain(|_| flags.next().copied().unwrap_or(true));
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

#[cfg(test)]
mod tests {
    use super::*;

    fn track(points: &[DVec3], r: f64, first: usize) -> Track {
        let radii = vec![r; points.len()];
        Track::widened_from(points, &radii, &Params::DEFAULT, None, first, SWEEP_CAP)
    }

    #[test]
    fn a_thinned_track_keeps_its_original_points_and_their_mapping() {
        // A straight branch of five points 6 radii apart: the resampler puts
        // several points between each two, of which thinning drops some.
        let points: Vec<DVec3> = (0..5)
            .map(|i| DVec3::new(6.0 * f64::from(i), 0.0, 0.0))
            .collect();
        let full = track(&points, 1.0, 0);
        let thin = full.clone().thinned();
        assert!(thin.samples.len() < full.samples.len());
        let n = thin.samples.len();
        for v in [
            thin.frames.len(),
            thin.counts.len(),
            thin.radii.len(),
            thin.arc.len(),
        ] {
            assert_eq!(v, n);
        }
        for (k, p) in points.iter().enumerate() {
            let s = &thin.samples[thin.originals[k]];
            assert!(s.original && s.source as usize == k && s.pos.distance(*p) < 1e-9);
        }
        // Arc lengths are still measured along the whole resampled curve.
        assert!((thin.arc[n - 1] - full.arc[full.samples.len() - 1]).abs() < 1e-12);
    }

    #[test]
    fn the_widest_factor_is_the_largest_widening() {
        let zigzag: Vec<DVec3> = (0..40)
            .map(|i| DVec3::new(0.8 * f64::from(i), if i % 2 == 0 { 0.0 } else { 0.4 }, 0.0))
            .collect();
        let t = track(&zigzag, 1.0, 0);
        let most = widening(&t).into_iter().fold(1.0, f64::max);
        assert!(most > 1.005);
        assert_eq!(t.widest(), most);
        let straight: Vec<DVec3> = (0..20)
            .map(|i| DVec3::new(f64::from(i), 0.0, 0.0))
            .collect();
        assert!((track(&straight, 1.0, 0).widest() - 1.0).abs() < 1e-3);
    }

    fn widening(t: &Track) -> Vec<f64> {
        (0..t.samples.len()).map(|i| t.widening(i)).collect()
    }

    #[test]
    fn a_straight_or_gently_bent_branch_is_not_widened() {
        let straight: Vec<DVec3> = (0..20)
            .map(|i| DVec3::new(f64::from(i), 0.0, 0.0))
            .collect();
        // A quarter circle of radius 20, sampled every unit: it bends at a
        // scale far above the tube's radius of 1.
        let arc: Vec<DVec3> = (0..32)
            .map(|i| {
                let a = f64::from(i) / 20.0;
                DVec3::new(20.0 * a.sin(), 20.0 * (1.0 - a.cos()), 0.0)
            })
            .collect();
        for points in [straight, arc] {
            for f in widening(&track(&points, 1.0, 0)) {
                assert!((f - 1.0).abs() < 1e-3, "factor {f}");
            }
        }
    }

    #[test]
    fn a_jittering_branch_is_widened_at_most_to_the_cap() {
        // Samples 0.8 radius apart, jumping 0.4 radius sideways each step,
        // as on EM traces.
        let points: Vec<DVec3> = (0..40)
            .map(|i| DVec3::new(0.8 * f64::from(i), if i % 2 == 0 { 0.0 } else { 0.4 }, 0.0))
            .collect();
        let f = widening(&track(&points, 1.0, 0));
        let middle = &f[f.len() / 4..3 * f.len() / 4];
        assert!(middle.iter().all(|&x| x > 1.005), "{middle:?}");
        assert!(
            f.iter().all(|&x| (1.0..=SWEEP_CAP + 1e-12).contains(&x)),
            "{f:?}"
        );
    }

    #[test]
    fn nothing_before_the_first_widened_point_is_widened_or_counted() {
        // A zigzag first segment (a soma's, say), then a straight branch.
        let mut points = vec![DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0)];
        points.extend((2..20).map(|i| DVec3::new(f64::from(i), 1.0, 0.0)));
        let whole = widening(&track(&points, 1.0, 0));
        let t = track(&points, 1.0, 1);
        let from_one = widening(&t);
        for (s, f) in t.samples.iter().zip(&from_one) {
            if s.source == 0 {
                assert_eq!(*f, 1.0);
            }
        }
        assert!(whole.iter().any(|&x| x > 1.005), "the bend is seen from 0");
        assert!(from_one.iter().sum::<f64>() < whole.iter().sum::<f64>());
    }
}
