//! The union's cross-section about each contour: contours that follow it.
//!
//! A contour is a circle about the spline, sized by the round cone's section
//! there ([`crate::spline::cone_section`]) and widened to the largest centred
//! disc the nearby samples' spheres hold ([`crate::spline::reach_of_spheres`]).
//! That disc is the *inscribed* one. Where the trace jitters by about its own
//! radius (electron-microscopy skeletons of fly neurons, z-steps of stack
//! traces) the union of round cones around the smoothed spline is wider than
//! that disc on the side each kink leans to, and a tube of circles sat about
//! 0.06 radii inside the union on average: FlyWire and larva traces lost 6–9 %
//! of their volume.
//!
//! So a contour whose plane the branch's *other* segments cut beyond its
//! circle gets a *profile*: in each of [`DIRECTIONS`] directions about its
//! centre, the distance at which a ray from the centre leaves the union of the
//! nearby round cones, less the distance at which it leaves the cones of the
//! sample's own segments (those whose axis passes nearest it), is added to the
//! circle's radius (at most [`MAX_STRETCH`] times it in all). Each contour
//! vertex is placed at the profile's distance in its direction, so the
//! contour stays star-shaped about its centre and the connection of
//! [`crate::tube`] applies unchanged.
//!
//! Why the excess over the own segments rather than the union's section
//! itself: where segments are long and the spline bows off their chord, the
//! section about the spline is off-centre, wider on one side and narrower on
//! the other; the circle already balances the two, and a profile that only
//! widened would add volume there (a rat CA1 pyramidal cell went from +1.5 %
//! to +8.9 % of the union's volume), while one that also narrowed pinched the
//! tube wherever the spline leaves the cones (a FlyWire neuron went from
//! −6.5 % to −12.7 %, with crossings). What other segments add is what a
//! jittering trace has and a smooth one does not.
//!
//! The round cones are taken as the union of the spheres swept along each
//! segment (a round cone is exactly the union of the spheres whose centres and
//! radii interpolate its ends'), sampled at a quarter of the smaller radius:
//! the exit along a ray is then an interval merge of ray–sphere intersections.
//! Like [`crate::spline::reach_of_spheres`], the branch's first point (its
//! branch point or soma sample) and the segment from it are left out: they
//! belong to what the branch grows out of. The first and last contours of a
//! track stay circles: joins, somas and tip caps are built on them.
//!
//! A profile's largest value becomes the track's polygon radius, so every test
//! that bounds a contour by its disc ([`crate::contour::DiscFrame`], the
//! volumes of [`crate::volume`]) stays conservative.

use glam::DVec3;

use crate::spline::Sample;

/// Directions of a profile, evenly spaced from the sample's first-vertex
/// direction; vertices between them interpolate linearly (32 gave the same
/// volumes on the corpus within 0.1 %, for twice the time).
pub const DIRECTIONS: usize = 16;

/// A profile reaches at most this many times the circle's radius: a contour
/// much wider than its own disc would tilt its bands into its neighbours'.
pub const MAX_STRETCH: f64 = 1.5;

/// Samples whose nearby spheres all lie within this fraction of the radius
/// of the contour's axis keep their circle.
const MIN_OFFSET: f64 = 0.01;

/// Profiles whose largest and smallest values differ by at most this are
/// left circles.
const SAME: f64 = 0.01;

/// The profiles of a track's samples.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Profiles {
    /// Per sample, the index of its profile in `values` (divided by
    /// [`DIRECTIONS`]), or `u32::MAX` for a circle.
    index: Vec<u32>,
    /// Distances over the polygon radius, [`DIRECTIONS`] per profile, each at
    /// most 1 (the polygon radius is the largest).
    values: Vec<f32>,
}

impl Profiles {
    /// No profile at all (every contour a circle).
    pub fn none(samples: usize) -> Profiles {
        Profiles {
            index: vec![u32::MAX; samples],
            values: Vec::new(),
        }
    }

    /// Computes the profiles of `samples` (with first-vertex directions
    /// `frames`) against the round cones of the branch's `points` and `radii`,
    /// and widens `poly_radii` (the polygon radii) to each profile's largest
    /// value.
    pub fn new(
        samples: &[Sample],
        frames: &[DVec3],
        poly_radii: &mut [f64],
        points: &[DVec3],
        radii: &[f64],
    ) -> Profiles {
        let mut out = Profiles::none(samples.len());
        let spheres = swept_spheres(points, radii);
        if spheres.is_empty() {
            return out;
        }
        let widest = spheres.iter().map(|s| s.1).fold(0.0, f64::max);
        let arcs: Vec<f64> = spheres.iter().map(|s| s.2).collect();
        // Arc length of each original point, for the samples' windows.
        let mut point_arc = vec![0.0; points.len()];
        for j in 1..points.len() {
            point_arc[j] = point_arc[j - 1] + points[j - 1].distance(points[j]);
        }
        let longest = (1..points.len())
            .map(|j| point_arc[j] - point_arc[j - 1])
            .fold(0.0, f64::max);
        let window = widest + longest;
        let mut near: Vec<(DVec3, f64, usize)> = Vec::new();
        let (mut own, mut all): (Vec<(DVec3, f64)>, Vec<(DVec3, f64)>) = (Vec::new(), Vec::new());
        let mut intervals: Vec<(f64, f64)> = Vec::new();
        let mut profile = [0.0f64; DIRECTIONS];
        for (i, s) in samples.iter().enumerate() {
            if i == 0 || i + 1 == samples.len() {
                // Track ends carry caps and joins built on circles.
                continue;
            }
            let at = point_arc[s.source as usize];
            let lo = arcs.partition_point(|&a| a < at - window);
            let hi = arcs.partition_point(|&a| a <= at + window);
            let r = s.radius;
            // The spheres the disc's plane cuts. Where all lie on the axis the
            // section is the centred disc the circle already is.
            near.clear();
            let mut off_axis: f64 = 0.0;
            for &(o, rho, _, seg) in &spheres[lo..hi] {
                let v = o - s.pos;
                let h = v.dot(s.tangent);
                if h.abs() >= rho {
                    continue;
                }
                off_axis = off_axis.max((v - h * s.tangent).length());
                near.push((o, rho, seg));
            }
            if off_axis <= MIN_OFFSET * r {
                continue;
            }
            // The sample's own segments (those whose axis passes nearest it;
            // both at an original point): what its circle stands for. Only
            // what the others add beyond them widens the contour.
            let (mut best, mut segs) = (f64::INFINITY, [usize::MAX; 2]);
            for &(_, _, seg) in &near {
                if seg == segs[0] || seg == segs[1] || seg + 1 >= points.len() {
                    continue;
                }
                let d = point_segment(s.pos, points[seg], points[seg + 1]);
                if d < best - 1e-9 * r {
                    (best, segs) = (d, [seg, usize::MAX]);
                } else if d <= best + 1e-9 * r {
                    segs[1] = seg;
                }
            }
            // Only spheres of other segments that reach out of the circle can
            // widen it.
            let widens = near.iter().any(|&(o, rho, seg)| {
                if seg == segs[0] || seg == segs[1] {
                    return false;
                }
                let v = o - s.pos;
                let h = v.dot(s.tangent);
                (v - h * s.tangent).length() + (rho * rho - h * h).sqrt() > (1.0 + SAME) * r
            });
            if !widens {
                continue;
            }
            own.clear();
            own.extend(
                near.iter()
                    .filter(|n| n.2 == segs[0] || n.2 == segs[1])
                    .map(|n| (n.0, n.1)),
            );
            all.clear();
            all.extend(near.iter().map(|n| (n.0, n.1)));
            let u = frames[i];
            let v = s.tangent.cross(u);
            let (mut most, mut least): (f64, f64) = (0.0, f64::INFINITY);
            for (k, slot) in profile.iter_mut().enumerate() {
                let theta = std::f64::consts::TAU * k as f64 / DIRECTIONS as f64;
                let d = theta.cos() * u + theta.sin() * v;
                let exit = exit_distance(s.pos, d, &all, &mut intervals);
                let base = exit_distance(s.pos, d, &own, &mut intervals);
                let excess = if base > 0.0 {
                    (exit - base).max(0.0)
                } else {
                    0.0
                };
                *slot = (1.0 + excess / r).min(MAX_STRETCH);
                most = most.max(*slot);
                least = least.min(*slot);
            }
            if most - least <= SAME {
                continue;
            }
            out.index[i] = (out.values.len() / DIRECTIONS) as u32;
            out.values
                .extend(profile.iter().map(|&p| (p / most) as f32));
            poly_radii[i] *= most;
        }
        out
    }

    /// The profile of the first `end` samples.
    pub fn prefix(&self, end: usize) -> Profiles {
        Profiles {
            index: self.index[..end].to_vec(),
            values: self.values.clone(),
        }
    }

    /// Whether sample `i` has a profile.
    pub fn shaped(&self, i: usize) -> bool {
        self.index.get(i).is_some_and(|&k| k != u32::MAX)
    }

    /// The distance over the polygon radius of sample `i` at angle `theta`
    /// from its first-vertex direction (1 for a circle).
    pub fn at(&self, i: usize, theta: f64) -> f64 {
        let Some(&k) = self.index.get(i).filter(|&&k| k != u32::MAX) else {
            return 1.0;
        };
        let p = &self.values[k as usize * DIRECTIONS..(k as usize + 1) * DIRECTIONS];
        let x = theta.rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU * DIRECTIONS as f64;
        let a = (x.floor() as usize).min(DIRECTIONS - 1);
        let f = x - a as f64;
        let b = (a + 1) % DIRECTIONS;
        f64::from(p[a]) * (1.0 - f) + f64::from(p[b]) * f
    }
}

/// The spheres swept along each segment from the branch's second point on,
/// a quarter of the smaller radius apart: (centre, radius, arc length along
/// the original points).
fn swept_spheres(points: &[DVec3], radii: &[f64]) -> Vec<(DVec3, f64, f64, usize)> {
    let mut out = Vec::new();
    let mut arc = 0.0;
    for j in 1..points.len() {
        let len = points[j - 1].distance(points[j]);
        arc += len;
        if j + 1 == points.len() {
            out.push((points[j], radii[j], arc, j - 1));
            break;
        }
        let (a, b) = (points[j], points[j + 1]);
        let (ra, rb) = (radii[j], radii[j + 1]);
        let d = a.distance(b);
        let step = 0.25 * ra.min(rb);
        let n = if step > 0.0 {
            ((d / step).ceil() as usize).clamp(1, 64)
        } else {
            1
        };
        for k in 0..n {
            let t = k as f64 / n as f64;
            out.push((a.lerp(b, t), ra + (rb - ra) * t, arc + d * t, j));
        }
    }
    out.retain(|s| s.1 > 0.0 && s.1.is_finite());
    out
}

/// Distance from `p` to the segment `a`–`b`.
fn point_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + ab * t)
}

/// Where the ray `c + t·d` (t ≥ 0) first leaves the union of `spheres`; 0 if
/// `c` lies in none.
fn exit_distance(
    c: DVec3,
    d: DVec3,
    spheres: &[(DVec3, f64)],
    intervals: &mut Vec<(f64, f64)>,
) -> f64 {
    intervals.clear();
    for &(o, rho) in spheres {
        let w = c - o;
        let b = w.dot(d);
        let disc = b * b - (w.length_squared() - rho * rho);
        if disc <= 0.0 {
            continue;
        }
        let q = disc.sqrt();
        let (t0, t1) = (-b - q, -b + q);
        if t1 > 0.0 {
            intervals.push((t0, t1));
        }
    }
    intervals.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
    let mut reach = 0.0;
    for &(t0, t1) in intervals.iter() {
        if t0 > reach {
            break;
        }
        reach = f64::max(reach, t1);
    }
    reach
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Params;
    use crate::track::Track;

    /// A branch along x whose points step `jog` sideways and back every
    /// `step`, radius `r`.
    fn zigzag(n: usize, step: f64, jog: f64, r: f64) -> Track {
        let pts: Vec<DVec3> = (0..n)
            .map(|i| DVec3::new(step * i as f64, if i % 2 == 1 { jog } else { 0.0 }, 0.0))
            .collect();
        Track::new(&pts, &vec![r; n], &Params::default(), None)
    }

    #[test]
    fn a_straight_branch_keeps_its_circles() {
        let t = zigzag(20, 1.0, 0.0, 1.0);
        assert!((0..t.samples.len()).all(|i| !t.profiles.shaped(i)));
    }

    #[test]
    fn a_jittering_branch_widens_where_its_kinks_reach_out() {
        let t = zigzag(20, 1.0, 0.8, 1.0);
        let shaped: Vec<usize> = (0..t.samples.len())
            .filter(|&i| t.profiles.shaped(i))
            .collect();
        assert!(shaped.len() > t.samples.len() / 4, "{shaped:?}");
        for &i in &shaped {
            // The polygon radius is the profile's largest distance: the
            // profile reaches 1 somewhere and never beyond it.
            let values: Vec<f64> = (0..64)
                .map(|k| {
                    t.profiles
                        .at(i, std::f64::consts::TAU * f64::from(k) / 64.0)
                })
                .collect();
            let most = values.iter().copied().fold(0.0, f64::max);
            let least = values.iter().copied().fold(f64::INFINITY, f64::min);
            assert!((most - 1.0).abs() < 1e-6, "{most}");
            assert!(least >= 1.0 / MAX_STRETCH - 1e-6 && least < most, "{least}");
            let circle = crate::contour::polygon_radius(t.samples[i].radius, t.counts[i]);
            assert!(t.radii[i] > circle && t.radii[i] <= MAX_STRETCH * circle + 1e-12);
        }
        // The ends stay circles.
        assert!(!t.profiles.shaped(0) && !t.profiles.shaped(t.samples.len() - 1));
    }

    #[test]
    fn a_ray_leaves_overlapping_spheres_at_the_far_one() {
        let s = [(DVec3::ZERO, 1.0), (DVec3::new(1.5, 0.0, 0.0), 1.0)];
        let mut iv = Vec::new();
        let t = exit_distance(DVec3::ZERO, DVec3::X, &s, &mut iv);
        assert!((t - 2.5).abs() < 1e-12);
        // A sphere beyond a gap does not count.
        let s = [(DVec3::ZERO, 1.0), (DVec3::new(3.0, 0.0, 0.0), 1.0)];
        assert!((exit_distance(DVec3::ZERO, DVec3::X, &s, &mut iv) - 1.0).abs() < 1e-12);
        // Outside every sphere: 0.
        let s = [(DVec3::new(5.0, 0.0, 0.0), 1.0)];
        assert_eq!(exit_distance(DVec3::ZERO, DVec3::X, &s, &mut iv), 0.0);
    }
}
