//! Resampling a branch with Catmull-Rom splines (paper §3.2, formula 1).
//!
//! Between original points P_i and P_{i+1} the resampler inserts
//! `δ = floor(D(P_i, P_{i+1}) · resolution / r_avg) + k1` samples (`k1 + 1` on the
//! branch's first segment, the paper's endpoint rule), where `r_avg` is the mean
//! radius of the branch's original points. So samples are about `r_avg` apart,
//! which matches the contours' edge length (formula 3): near-equilateral
//! triangles. Original points are kept; the radius is the cross-section of the
//! segment's round cone ([`cone_section`]: linear where the radius changes
//! slowly); the tangent is the spline's derivative.
//!
//! We use the *centripetal* Catmull-Rom parameterisation (α = ½): on the unevenly
//! spaced points of real traces the uniform one overshoots and can form cusps or
//! loops, the centripetal one provably cannot. End segments use reflected phantom
//! points, which gives straight ends.
//! A segment's spline is blended toward its chord where it would stray from it
//! by more than [`DEVIATION_BOUND`] of the radius: the union of round cones the
//! mesh stands for runs along the chords.
//!
//! Contour orientation: [`super::tangents::smooth_tangents`] then turns each tangent into the
//! direction of the curve over one radius either side, the scale at which a disc
//! of that radius sees the skeleton.
//!
//! Robustness: points closer than a tiny fraction of `r_avg` to their predecessor
//! are merged first (keeping the larger radius), and a tangent that vanishes
//! (a cusp) falls back to the chord, so duplicate and near-duplicate points never
//! produce NaN tangents.

use glam::DVec3;

/// At most this many samples are inserted into one segment (bounds memory on
/// absurd inputs: a kilometre-long segment on a nanometre-thin branch).
pub const MAX_INSERTED_PER_SEGMENT: usize = 100_000;

/// One resampled point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Position on the spline.
    pub pos: DVec3,
    /// Unit tangent (direction of travel).
    pub tangent: DVec3,
    /// Interpolated radius.
    pub radius: f64,
    /// Index into the branch's original points of the nearest one.
    pub source: u32,
    /// Whether this is an original point (u = 0 of its segment, or the last point).
    pub original: bool,
}

/// Resamples the polyline `points` (with `radii`) as formula (1) prescribes.
/// `r_avg` is the branch's mean radius divided by the resolution factor.
pub fn resample(points: &[DVec3], radii: &[f64], r_avg: f64, k1: u32) -> Vec<Sample> {
    debug_assert_eq!(points.len(), radii.len());
    // Merge near-duplicates so every segment has a usable length.
    let eps = (1e-6 * r_avg).max(
        1e-12
            * points
                .iter()
                .map(|p| p.abs().max_element())
                .fold(0.0, f64::max),
    );
    let mut pts: Vec<DVec3> = Vec::with_capacity(points.len());
    let mut rad: Vec<f64> = Vec::with_capacity(points.len());
    let mut src: Vec<u32> = Vec::with_capacity(points.len());
    for (i, (&p, &r)) in points.iter().zip(radii).enumerate() {
        if let Some(&last) = pts.last()
            && p.distance(last) <= eps
        {
            let k = rad.len() - 1;
            rad[k] = rad[k].max(r);
            continue;
        }
        pts.push(p);
        rad.push(r);
        src.push(i as u32);
    }
    let n = pts.len();
    if n == 1 {
        return vec![Sample {
            pos: pts[0],
            tangent: DVec3::Z,
            radius: rad[0],
            source: src[0],
            original: true,
        }];
    }
    let mut out = Vec::with_capacity(n * 4);
    for i in 0..n - 1 {
        let p1 = pts[i];
        let p2 = pts[i + 1];
        let p0 = if i > 0 { pts[i - 1] } else { 2.0 * p1 - p2 };
        let p3 = if i + 2 < n { pts[i + 2] } else { 2.0 * p2 - p1 };
        let chord = (p2 - p1).normalize();
        let d = p1.distance(p2);
        let seg = CentripetalSegment::new(p0, p1, p2, p3)
            .bounded(DEVIATION_BOUND * rad[i].min(rad[i + 1]));
        let k = if i == 0 { k1 + 1 } else { k1 } as usize;
        let inserted = ((d / r_avg).floor() as usize)
            .saturating_add(k)
            .min(MAX_INSERTED_PER_SEGMENT);
        let steps = inserted + 1;
        for j in 0..steps {
            let u = j as f64 / steps as f64;
            let pos = if j == 0 { p1 } else { seg.point(u) };
            let t = seg.derivative(u);
            let tangent = if t.length_squared() > 1e-24 * d * d && t.dot(chord) > 0.0 {
                t.normalize()
            } else {
                chord
            };
            out.push(Sample {
                pos,
                tangent,
                radius: if j == 0 && i > 0 {
                    // A joint: the wider of the two cones' sections.
                    let d0 = pts[i - 1].distance(p1);
                    cone_section(rad[i], rad[i + 1], d, 0.0).max(cone_section(
                        rad[i - 1],
                        rad[i],
                        d0,
                        d0,
                    ))
                } else {
                    // At the point's own place along the segment: the
                    // centripetal parameter runs unevenly (a long segment
                    // after a short one is crossed fast at first), and a
                    // steep cone's section taken at u·d stands wide of the
                    // union's.
                    cone_section(rad[i], rad[i + 1], d, (pos - p1).dot(chord).clamp(0.0, d))
                },
                source: if u <= 0.5 { src[i] } else { src[i + 1] },
                original: j == 0,
            });
        }
    }
    let last = n - 1;
    let t = CentripetalSegment::new(
        if last >= 2 {
            pts[last - 2]
        } else {
            2.0 * pts[last - 1] - pts[last]
        },
        pts[last - 1],
        pts[last],
        2.0 * pts[last] - pts[last - 1],
    )
    .derivative(1.0);
    let chord = (pts[last] - pts[last - 1]).normalize();
    out.push(Sample {
        pos: pts[last],
        tangent: if t.length_squared() > 0.0 && t.dot(chord) > 0.0 {
            t.normalize()
        } else {
            chord
        },
        radius: cone_section(
            rad[last - 1],
            rad[last],
            pts[last - 1].distance(pts[last]),
            pts[last - 1].distance(pts[last]),
        ),
        source: src[last],
        original: true,
    });
    out
}

/// Widens each sample to the largest disc about it, in its own plane, that
/// the spheres of the branch's nearby samples hold (the first point, the
/// branch point or soma sample, belongs to what the branch grows out of and
/// is left out).
///
/// A round cone's section covers only its own segment, but the union also
/// holds each sample's whole sphere, which reaches over the neighbouring
/// segments when they are shorter than the radius (auto-traced and EM
/// skeletons step half a radius at a time with radii jumping), and a tube
/// following the segments' own cones loses a few per cent of such a cell's
/// volume. A sphere off the disc's axis counts
/// only by what it holds around the disc's centre (its section's radius less
/// the offset), so the disc never leaves the spheres' sections.
pub fn reach_of_spheres(samples: &mut [Sample], points: &[DVec3], radii: &[f64]) {
    let n = points.len();
    if n < 2 {
        return;
    }
    let widest = radii[1..].iter().copied().fold(0.0, f64::max);
    let mut arc = vec![0.0; n];
    for j in 1..n {
        arc[j] = arc[j - 1] + points[j - 1].distance(points[j]);
    }
    let longest = (1..n).map(|j| arc[j] - arc[j - 1]).fold(0.0, f64::max);
    // A sphere reaches a disc only within its radius along the curve, and a
    // disc lies within one segment of its nearest original point.
    let window = widest + longest;
    for s in samples.iter_mut() {
        let at = arc[s.source as usize];
        let lo = arc.partition_point(|&a| a < at - window).max(1);
        let hi = arc.partition_point(|&a| a <= at + window);
        for j in lo..hi {
            let v = points[j] - s.pos;
            let h = v.dot(s.tangent);
            let r = radii[j];
            if h.abs() >= r || r <= s.radius {
                continue;
            }
            let off = (v - h * s.tangent).length();
            s.radius = s.radius.max((r * r - h * h).sqrt() - off);
        }
    }
}

/// Radius of the cross-section at distance `x` along the axis of the round cone
/// of length `d` between spheres of radii `r1` and `r2` (their convex hull).
///
/// Where the radius changes fast along a segment the hull's flank is tangent to
/// both spheres, not the line between their radii: near the thin end it is
/// wider than the linear radius by up to `1 / cos φ`, with `sin φ = (r1 − r2) / d`.
/// Sizing contours by the hull keeps area and volume on the union of round
/// cones where a neurite tapers steeply or leaves a thick parent.
pub fn cone_section(r1: f64, r2: f64, d: f64, x: f64) -> f64 {
    let sphere = |r: f64, dx: f64| (r * r - dx * dx).max(0.0).sqrt();
    let spheres = sphere(r1, x).max(sphere(r2, d - x));
    if d <= 0.0 || (r1 - r2).abs() >= d {
        return spheres;
    }
    let sin = (r1 - r2) / d;
    let cos = (1.0 - sin * sin).sqrt();
    let (xa, xb) = (r1 * sin, d + r2 * sin);
    if x <= xa || x >= xb {
        return spheres;
    }
    let (pa, pb) = (r1 * cos, r2 * cos);
    (pa + (pb - pa) * (x - xa) / (xb - xa)).max(spheres)
}

/// A segment's spline strays from its chord by at most this fraction of the
/// thinner end's radius.
///
/// The union of round cones runs along the chords; the spline through the
/// same points bulges off a long segment between bends by a share of its
/// length, not of the radius: on segments a hundred radii long, by many
/// radii. Held within 3 % of the radius, the contour centres stay within the
/// polygon's own error of the union's axis, so the surface's 95th-percentile
/// distance from the union stays near 5 % of the local radius (a tenth let
/// it reach 10 %), and straight stretches stay straight enough to thin.
pub const DEVIATION_BOUND: f64 = 0.03;

/// One centripetal Catmull-Rom segment from p1 to p2 as a cubic a·u³ + b·u² + c·u + d.
#[derive(Debug, Clone, Copy)]
struct CentripetalSegment {
    a: DVec3,
    b: DVec3,
    c: DVec3,
    d: DVec3,
}

impl CentripetalSegment {
    fn new(p0: DVec3, p1: DVec3, p2: DVec3, p3: DVec3) -> Self {
        let knot = |a: DVec3, b: DVec3| a.distance(b).sqrt().max(1e-150);
        let (t01, t12, t23) = (knot(p0, p1), knot(p1, p2), knot(p2, p3));
        let m1 = p2 - p1 + t12 * ((p1 - p0) / t01 - (p2 - p0) / (t01 + t12));
        let m2 = p2 - p1 + t12 * ((p3 - p2) / t23 - (p3 - p1) / (t12 + t23));
        CentripetalSegment {
            a: 2.0 * (p1 - p2) + m1 + m2,
            b: -3.0 * (p1 - p2) - 2.0 * m1 - m2,
            c: m1,
            d: p1,
        }
    }

    /// The segment blended toward its chord, p1 + u·(p2 − p1), so that it
    /// strays from the chord's line by at most `bound` (the largest distance
    /// taken over 16 steps of u): the blend scales the spline's offset from
    /// the chord by the same factor at every u, and keeps its ends.
    fn bounded(self, bound: f64) -> Self {
        let (p1, p2) = (self.d, self.a + self.b + self.c + self.d);
        let span = p2 - p1;
        let len2 = span.length_squared();
        if len2 <= 0.0 || !bound.is_finite() {
            return self;
        }
        let stray = (1..16)
            .map(|k| {
                let v = self.point(k as f64 / 16.0) - p1;
                (v - span * (v.dot(span) / len2)).length()
            })
            .fold(0.0, f64::max);
        if stray <= bound {
            return self;
        }
        let s = bound / stray;
        // The chord as a cubic: 0·u³ + 0·u² + span·u + p1.
        CentripetalSegment {
            a: self.a * s,
            b: self.b * s,
            c: span + (self.c - span) * s,
            d: p1,
        }
    }

    fn point(&self, u: f64) -> DVec3 {
        ((self.a * u + self.b) * u + self.c) * u + self.d
    }

    fn derivative(&self, u: f64) -> DVec3 {
        (3.0 * self.a * u + 2.0 * self.b) * u + self.c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_segment_between_sharp_turns_stays_near_its_chord() {
        // Short steps up, a 60-long run along x, short steps down: the
        // unbounded spline bulges off the run by several units.
        let pts = [
            DVec3::new(0.0, -2.0, 0.0),
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(60.0, 0.0, 0.0),
            DVec3::new(60.0, 2.0, 0.0),
        ];
        let r = 0.4;
        let unbounded = CentripetalSegment::new(pts[0], pts[1], pts[2], pts[3]);
        let off = |p: DVec3| p.y.hypot(p.z);
        let bulge = (1..64)
            .map(|k| off(unbounded.point(k as f64 / 64.0)))
            .fold(0.0, f64::max);
        assert!(bulge > 2.0 * r, "the test needs a bulging spline: {bulge}");
        let s = resample(&pts, &[r; 4], r, 1);
        // The run's samples (those of the short segments lie within 0.1 of
        // x = 0 and x = 60).
        let run: Vec<&Sample> = s
            .iter()
            .filter(|x| x.pos.x > 0.5 && x.pos.x < 59.5)
            .collect();
        assert!(run.len() > 100, "{}", run.len());
        for x in run {
            // 16 steps of u find the largest stray to within a few per cent.
            assert!(off(x.pos) <= 1.05 * DEVIATION_BOUND * r, "{x:?}");
        }
        // Original points are kept, and the tangents still run along x.
        for p in &pts {
            assert!(s.iter().any(|x| x.original && x.pos == *p), "{p}");
        }
        assert!(
            s.iter()
                .filter(|x| x.pos.x > 1.0 && x.pos.x < 59.0)
                .all(|x| x.tangent.x > 0.99),
        );
    }

    #[test]
    fn a_gentle_bend_keeps_its_spline() {
        // Where the spline strays less than the bound, the blend leaves it be.
        let seg = CentripetalSegment::new(
            DVec3::new(-1.0, 0.01, 0.0),
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(2.0, 0.01, 0.0),
        );
        let b = seg.bounded(0.1);
        for k in 0..=8 {
            let u = k as f64 / 8.0;
            assert_eq!(seg.point(u), b.point(u));
        }
    }

    #[test]
    fn a_bead_widens_its_short_neighbours_within_its_sphere() {
        // Unit steps along x, a bead of radius 3 at x = 2 among radius 1,
        // and the branch point at x = 0 wider than its neighbour.
        let pts: Vec<DVec3> = (0..5).map(|i| DVec3::new(i as f64, 0.0, 0.0)).collect();
        let radii = [1.5, 1.0, 3.0, 1.0, 1.0];
        let mut s = resample(&pts, &radii, 0.5, 1);
        let before: Vec<f64> = s.iter().map(|x| x.radius).collect();
        reach_of_spheres(&mut s, &pts, &radii);
        for (x, r0) in s.iter().zip(&before) {
            let d = x.pos.x - 2.0;
            // Never narrower, never wider than the widest sphere's section
            // (the branch point's is left out), and the bead's section
            // wherever it is the wider.
            let bead = (9.0 - d * d).max(0.0).sqrt();
            let sphere = |c: f64, r: f64| (r * r - (x.pos.x - c).powi(2)).max(0.0).sqrt();
            let widest = (1..5)
                .map(|j| sphere(j as f64, radii[j]))
                .fold(*r0, f64::max);
            assert!(x.radius >= *r0 && x.radius >= bead - 1e-12, "{x:?}");
            assert!(x.radius <= widest + 1e-12, "{x:?} wider than {widest}");
        }
        // At x = 1 the bead's section: √(9 − 1).
        let at1 = s.iter().find(|x| (x.pos.x - 1.0).abs() < 1e-9).unwrap();
        assert!((at1.radius - 8f64.sqrt()).abs() < 1e-9, "{at1:?}");
    }

    #[test]
    fn a_sphere_off_the_axis_counts_by_what_it_holds_about_the_centre() {
        // A sharp bend: the sample at (2, 2) lies off the disc's axis at x = 1.
        let pts = [
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
        ];
        let mut s = vec![Sample {
            pos: DVec3::new(0.5, 0.0, 0.0),
            tangent: DVec3::X,
            radius: 0.5,
            source: 1,
            original: false,
        }];
        reach_of_spheres(&mut s, &pts, &[0.5, 0.5, 3.0]);
        // Offset along the axis 0.5, off it 2: √(9 − 0.25) − 2.
        assert!(
            (s[0].radius - (8.75f64.sqrt() - 2.0)).abs() < 1e-12,
            "{:?}",
            s[0]
        );
    }

    #[test]
    fn formula_one_counts_and_keeps_original_points() {
        // Two segments of length 10 with r_avg = 2: floor(10/2) + k1 inserted,
        // +1 on the first segment: 7 and 6 inserted, plus 3 original points.
        let pts = [
            DVec3::ZERO,
            DVec3::new(10.0, 0.0, 0.0),
            DVec3::new(20.0, 0.0, 0.0),
        ];
        let s = resample(&pts, &[2.0, 2.0, 2.0], 2.0, 1);
        assert_eq!(s.len(), 7 + 6 + 3);
        let originals: Vec<DVec3> = s.iter().filter(|x| x.original).map(|x| x.pos).collect();
        assert_eq!(originals, pts.to_vec());
        assert_eq!(
            s.iter()
                .filter(|x| x.original)
                .map(|x| x.source)
                .collect::<Vec<_>>(),
            vec![0, 1, 2]
        );
        // A straight line stays straight with unit tangents along it.
        for x in &s {
            assert!(x.pos.y.abs() < 1e-12 && x.pos.z.abs() < 1e-12);
            assert!((x.tangent - DVec3::X).length() < 1e-9);
        }
    }

    #[test]
    fn radius_follows_the_round_cone() {
        // A gentle taper: the hull's section is the linear radius within 0.2 %.
        let pts = [DVec3::ZERO, DVec3::new(40.0, 0.0, 0.0)];
        let s = resample(&pts, &[1.0, 3.0], 1.0, 1);
        for x in &s {
            let linear = 1.0 + 2.0 * x.pos.x / 40.0;
            assert!(x.radius >= linear - 1e-12 && x.radius < linear * 1.002);
        }
        // A steep one: at the thin end the section is r / cos φ.
        let (r1, r2, d) = (6.0f64, 1.0f64, 10.0f64);
        let cos = (1.0 - ((r1 - r2) / d).powi(2)).sqrt();
        let at_end = cone_section(r1, r2, d, d);
        let want = r1 * cos + (r2 * cos - r1 * cos) * (d - r1 * 0.5) / (d + r2 * 0.5 - r1 * 0.5);
        assert!((at_end - want).abs() < 1e-12 && at_end > r2);
        // At the thick end's centre, its own sphere.
        assert!((cone_section(r1, r2, d, 0.0) - r1).abs() < 1e-12);
        // One sphere inside the other: the larger sphere's section.
        assert!((cone_section(5.0, 1.0, 2.0, 1.0) - 24f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn duplicate_and_near_duplicate_points_give_finite_tangents() {
        let pts = [
            DVec3::ZERO,
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0 + 1e-13, 1e-13, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 1e-9),
        ];
        let s = resample(&pts, &[1.0; 6], 0.5, 1);
        for x in &s {
            assert!(x.pos.is_finite() && x.tangent.is_finite(), "{x:?}");
            assert!((x.tangent.length() - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn single_point_branch() {
        let s = resample(&[DVec3::ONE, DVec3::ONE], &[1.0, 2.0], 1.0, 1);
        assert_eq!(s.len(), 1);
        assert_eq!(s[0].radius, 2.0);
    }

    #[test]
    fn centripetal_spline_does_not_overshoot_a_sharp_corner() {
        // A long leg then a tiny step back: uniform Catmull-Rom would loop.
        let pts = [
            DVec3::ZERO,
            DVec3::new(10.0, 0.0, 0.0),
            DVec3::new(10.2, 0.3, 0.0),
            DVec3::new(10.0, 10.0, 0.0),
        ];
        let s = resample(&pts, &[0.5; 4], 0.5, 1);
        let max_x = s.iter().map(|x| x.pos.x).fold(f64::MIN, f64::max);
        assert!(max_x < 10.6, "overshoot to {max_x}");
    }
}
