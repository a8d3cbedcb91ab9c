//! Round-cone volumes of tracks: where a tube may start.
//!
//! The paper drops a secondary's contours "situated in the volume of the
//! primary branch". We read "volume" as the union of round cones of the
//! resampled skeleton (each segment with its polygon radii at both ends), and
//! extend it to every branch built before the secondary that passes near its
//! branch point: siblings leaving a multifurcation in similar directions
//! overlap each other as much as their primary, and a secondary that starts
//! inside a sibling must grow out of that sibling's surface, not through it.

use glam::DVec3;

use crate::kernel::hash::FastMap;
use crate::kernel::round_cone::RoundCone;
use crate::skeleton::track::Track;

/// The first track point of a secondary whose contour touches none of the
/// given round cones (`(a, b, r_a, r_b)` segments of the primary near the branch
/// point), with a margin of a tenth of the secondary's radius; `None` if every
/// contour of the branch touches them (the branch is hidden inside).
pub fn first_outside(track: &Track, cones: &[RoundCone]) -> Option<usize> {
    first_outside_from(track, 0, cones)
}

/// [`first_outside`] starting the search at point `from`.
pub fn first_outside_from(track: &Track, from: usize, cones: &[RoundCone]) -> Option<usize> {
    let mut ring: Vec<DVec3> = Vec::new();
    // The cone that touched the last contour is asked first.
    let mut hint = None;
    (from..track.samples.len()).find(|&i| {
        let s = &track.samples[i];
        let r = track.radii[i];
        let margin = 0.1 * r;
        let u = track.frames[i];
        let v = s.tangent.cross(u);
        let m = track.counts[i];
        ring.clear();
        ring.extend((0..m).map(|j| {
            let th = std::f64::consts::TAU * f64::from(j) / f64::from(m);
            s.pos + r * (th.cos() * u + th.sin() * v)
        }));
        let touches = |&RoundCone { a, ra, b, rb }: &RoundCone| {
            // Neither test can pass when the disc's centre is farther from the
            // cone's axis than the disc's radius plus the cone's.
            if !may_reach(s.pos, r + margin, RoundCone { a, ra, b, rb }) {
                return false;
            }
            // A contour vertex inside the cone, or the cone's axis crossing the disc.
            ring.iter().any(|&p| inside_cone(p, a, b, ra, rb, margin))
                || axis_crosses_disc(a, b, ra.max(rb), s.pos, s.tangent, r)
        };
        !any_hinted(&mut hint, || cones, touches)
    })
}

/// Whether one of the cones `cones()` gives passes `test`, asking `hint`
/// first (one of those cones, or none) and making the one that passes the
/// hint. Inside a primary (or a blob of radius codes, where every cone
/// reaches every contour) neighbouring vertices and contours lie in the
/// same cone, so a test costs one cone instead of all; the answer does not
/// depend on the order the cones are asked in. `cones` is called only when
/// the hint fails, so a caller can build the list lazily.
fn any_hinted<'c>(
    hint: &mut Option<RoundCone>,
    cones: impl FnOnce() -> &'c [RoundCone],
    test: impl Fn(&RoundCone) -> bool,
) -> bool {
    if hint.as_ref().is_some_and(&test) {
        return true;
    }
    match cones().iter().find(|c| test(c)) {
        Some(&c) => {
            *hint = Some(c);
            true
        }
        None => false,
    }
}

/// Whether cone `c` can hold a point within `r` of `p`: its axis comes
/// closer to `p` than its larger radius plus `r`.
fn may_reach(p: DVec3, r: f64, RoundCone { a, ra, b, rb }: RoundCone) -> bool {
    let reach = r + ra.max(rb);
    point_segment_distance_sq(p, a, b) < reach * reach
}

/// The fraction of the vertices of the contour of track point `i` that lie
/// outside every one of `cones` (with their linear radius).
///
/// `hint` is a cone that held a vertex of an earlier contour, asked first
/// (inside a primary, neighbouring contours lie in the same cone, so a
/// vertex costs one test instead of one per cone). The fraction does not
/// depend on it: it is asked only
/// where it may reach the contour, which makes it one of the cones the
/// vertices are tested against.
pub fn fraction_outside(
    track: &Track,
    i: usize,
    cones: &[RoundCone],
    hint: &mut Option<RoundCone>,
) -> f64 {
    let s = &track.samples[i];
    let m = track.counts[i];
    let r = track.radii[i];
    let mut held = hint.filter(|&c| may_reach(s.pos, r, c));
    // The cones that cannot hold a point of the contour are left out once,
    // not once per vertex, and only if a vertex is not in the hinted cone.
    let mut reach: Option<Vec<RoundCone>> = None;
    let outside = crate::skeleton::contour::ring(s.pos, s.tangent, track.frames[i], r, m)
        .filter(|&p| {
            let reach = &mut reach;
            let reach = move || {
                // Moved out of the closure (not reborrowed), so the list
                // outlives the call.
                let reach = reach;
                reach
                    .get_or_insert_with(|| {
                        cones
                            .iter()
                            .copied()
                            .filter(|&c| may_reach(s.pos, r, c))
                            .collect()
                    })
                    .as_slice()
            };
            !any_hinted(&mut held, reach, |&RoundCone { a, ra, b, rb }| {
                inside_cone(p, a, b, ra, rb, 0.0)
            })
        })
        .count();
    if held.is_some() {
        *hint = held;
    }
    outside as f64 / f64::from(m)
}

/// The volume of the disc slices of track points `from..to`: each contour's
/// area times its share of the arc.
pub fn slices(track: &Track, from: usize, to: usize, weight: impl Fn(usize) -> f64) -> f64 {
    let n = track.samples.len();
    (from..to.min(n))
        .map(|i| {
            let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
            let share = 0.5 * (track.arc[b] - track.arc[a]);
            std::f64::consts::PI * track.radii[i] * track.radii[i] * share * weight(i)
        })
        .sum()
}

/// How deep, in its own radii, a sample must lie in the round cones that
/// replace its skipped contour for the mesh to be sure to hold it: the
/// band between two contours is a ruled surface of polygon edges, not the
/// cone, and inside it by up to a few per cent of the radius, more where
/// the contours tilt.
pub const SAMPLE_DEPTH: f64 = 0.3;

/// An original segment of a track whose skipped contours reach out of what
/// replaced them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Skipped {
    /// The segment: the index of its first original point.
    pub segment: u32,
    /// The volume its skipped contours leave out, estimated from their
    /// slices.
    pub gain: f64,
    /// Whether an original point of the trace (a sample) among them lies
    /// outside what replaced them: without the segment's filler the mesh
    /// would leave that sample out.
    pub holds_sample: bool,
}

impl Skipped {
    /// `self` and `other`, of the same segment, as one.
    pub fn merged(self, other: Skipped) -> Skipped {
        Skipped {
            gain: self.gain + other.gain,
            holds_sample: self.holds_sample || other.holds_sample,
            ..self
        }
    }
}

/// The original segments of `track` (index of their first point) whose
/// skipped contours reach out of what replaced them, with the volume they
/// leave out, estimated from the contours' slices: between two kept
/// contours (track points `kept`) the band's round cone; after the last, up to track point `tail`, the
/// band's cone and the end dome (of height `dome`).
///
/// The paper skips a contour that crosses its predecessor, and the band
/// from the kept one before to the next kept one stands for the skipped
/// stretch. That holds on a smooth bend; where the trace jogs (a spike of
/// one sample, a zig-zag of segments a few radii long, as on electron
/// microscopy traces) the skipped contours lie well off that band and the
/// segments' round cones are lost: 4 % of a fly larva neuron's volume in
/// segments missing 90 % of theirs or more. Each such segment gets a filler
/// of its own round cone (see the module documentation).
pub fn skipped_segments(track: &Track, kept: &[usize], tail: usize, dome: f64) -> Vec<Skipped> {
    let cone = |j: usize, k: usize| RoundCone {
        a: track.samples[j].pos,
        ra: track.radii[j],
        b: track.samples[k].pos,
        rb: track.radii[k],
    };
    let mut out = Vec::new();
    for w in kept.windows(2) {
        let band = [cone(w[0], w[1])];
        out.extend(segment_gains(track, w[0] + 1..w[1], &band));
    }
    let last = kept[kept.len() - 1];
    let mut end = vec![RoundCone::sphere(track.samples[last].pos, dome)];
    if kept.len() > 1 {
        end.push(cone(kept[kept.len() - 2], last));
    }
    out.extend(segment_gains(
        track,
        last + 1..tail.min(track.samples.len()),
        &end,
    ));
    out
}

/// Per original segment of `track` (index of its first point), the volume
/// of the contours of track points `points` outside every one of `cones`,
/// estimated from their slices, and whether an original point among them
/// lies outside every cone. An original point counts for the segment it
/// starts (the last one, for the one it ends): that segment's filler holds
/// it in its dome.
pub fn segment_gains(
    track: &Track,
    points: std::ops::Range<usize>,
    cones: &[RoundCone],
) -> Vec<Skipped> {
    let last = track.originals.len().saturating_sub(2);
    let mut out: Vec<Skipped> = Vec::new();
    let mut hint = None;
    for i in points {
        let w = fraction_outside(track, i, cones, &mut hint);
        if w <= 0.0 {
            continue;
        }
        let s = &track.samples[i];
        let skipped = Skipped {
            segment: (track
                .originals
                .partition_point(|&o| o <= i)
                .saturating_sub(1))
            .min(last) as u32,
            gain: slices(track, i, i + 1, |_| w),
            holds_sample: s.original
                && !cones.iter().any(|c| {
                    inside_cone(s.pos, c.a, c.b, c.ra, c.rb, -SAMPLE_DEPTH * track.radii[i])
                }),
        };
        match out.last_mut() {
            Some(o) if o.segment == skipped.segment => *o = o.merged(skipped),
            _ => out.push(skipped),
        }
    }
    out
}

/// The parameter in [0, 1] of the point of segment `a`-`b` nearest to `p`.
fn nearest_on_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    if l2 > 0.0 {
        ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

fn point_segment_distance_sq(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    p.distance_squared(a.lerp(b, nearest_on_segment(p, a, b)))
}

fn inside_cone(p: DVec3, a: DVec3, b: DVec3, ra: f64, rb: f64, margin: f64) -> bool {
    let t = nearest_on_segment(p, a, b);
    let r = ra + (rb - ra) * t;
    p.distance(a.lerp(b, t)) < r + margin
}

fn axis_crosses_disc(a: DVec3, b: DVec3, r_cone: f64, c: DVec3, n: DVec3, r: f64) -> bool {
    let (da, db) = ((a - c).dot(n), (b - c).dot(n));
    if da * db > 0.0 {
        return false;
    }
    let t = if (da - db).abs() > 0.0 {
        da / (da - db)
    } else {
        0.0
    };
    let x = a + (b - a) * t;
    x.distance(c) < r + r_cone
}

/// The round cones of `track` between resampled points `from` and `to`.
pub fn cones(track: &Track, from: usize, to: usize) -> Vec<RoundCone> {
    let to = to.min(track.samples.len().saturating_sub(1));
    if from >= to {
        let i = from.min(track.samples.len() - 1);
        let p = track.samples[i].pos;
        return vec![RoundCone::sphere(p, track.radii[i])];
    }
    (from..to)
        .map(|i| RoundCone {
            a: track.samples[i].pos,
            ra: track.radii[i],
            b: track.samples[i + 1].pos,
            rb: track.radii[i + 1],
        })
        .collect()
}

/// Round cones of tracks, bucketed in a uniform grid so the cones near a
/// point can be listed; tracks are added one by one, so an index holds just
/// the branches a query may return.
#[derive(Clone)]
pub struct ConeIndex {
    cell: f64,
    grid: FastMap<[i64; 3], Vec<(u32, u32)>>,
    /// Cones too large for the grid (absurd radii), always checked.
    large: Vec<(u32, u32)>,
}

impl ConeIndex {
    /// An index with no cones yet, its cells sized for `tracks` (8 times
    /// their median radius), to which tracks are added one by one.
    pub fn empty_for(tracks: &[Track]) -> ConeIndex {
        let mut sizes: Vec<f64> = tracks
            .iter()
            .flat_map(|t| t.radii.iter().step_by(1 + t.radii.len() / 64).copied())
            .collect();
        sizes.sort_by(f64::total_cmp);
        let cell = 8.0
            * sizes
                .get(sizes.len() / 2)
                .copied()
                .unwrap_or(1.0)
                .max(1e-300);
        ConeIndex {
            cell,
            grid: FastMap::default(),
            large: Vec::new(),
        }
    }

    /// Adds the segments of `t`, the track of branch `b`.
    pub fn add(&mut self, b: u32, t: &Track) {
        let cell = self.cell;
        for i in 0..t.samples.len().saturating_sub(1).max(1) {
            let j = (i + 1).min(t.samples.len() - 1);
            let r = t.radii[i].max(t.radii[j]);
            let (p, q) = (t.samples[i].pos, t.samples[j].pos);
            let lo = ((p.min(q) - DVec3::splat(r)) / cell).floor().as_i64vec3();
            let hi = ((p.max(q) + DVec3::splat(r)) / cell).floor().as_i64vec3();
            let n = (hi - lo + 1).as_dvec3();
            if n.x * n.y * n.z > 512.0 {
                self.large.push((b, i as u32));
                continue;
            }
            for x in lo.x..=hi.x {
                for y in lo.y..=hi.y {
                    for z in lo.z..=hi.z {
                        self.grid.entry([x, y, z]).or_default().push((b, i as u32));
                    }
                }
            }
        }
    }

    /// The cones that come within `reach` of `p`.
    pub fn near(&self, tracks: &[Track], p: DVec3, reach: f64) -> Vec<RoundCone> {
        let lo = ((p - DVec3::splat(reach)) / self.cell).floor();
        let hi = ((p + DVec3::splat(reach)) / self.cell).floor();
        // Counted in f64: a reach far beyond the grid saturates i64 cells.
        let n = hi - lo + 1.0;
        let (lo, hi) = (lo.as_i64vec3(), hi.as_i64vec3());
        let mut seen: crate::kernel::hash::FastSet<(u32, u32)> =
            crate::kernel::hash::FastSet::default();
        let mut out = Vec::new();
        let mut consider = |b: u32, i: u32, out: &mut Vec<RoundCone>| {
            if !seen.insert((b, i)) {
                return;
            }
            let t = &tracks[b as usize];
            let j = (i as usize + 1).min(t.samples.len() - 1);
            let (a, c) = (t.samples[i as usize].pos, t.samples[j].pos);
            let (ra, rc) = (t.radii[i as usize], t.radii[j]);
            if crate::kernel::predicates::segment_distance(a, c, p, p) <= reach + ra.max(rc) {
                out.push(RoundCone {
                    a,
                    ra,
                    b: c,
                    rb: rc,
                });
            }
        };
        for &(b, i) in &self.large {
            consider(b, i, &mut out);
        }
        if n.x * n.y * n.z <= (self.grid.len() as f64).max(64.0) {
            for x in lo.x..=hi.x {
                for y in lo.y..=hi.y {
                    for z in lo.z..=hi.z {
                        for &(b, i) in self.grid.get(&[x, y, z]).map_or(&[][..], |v| &v[..]) {
                            consider(b, i, &mut out);
                        }
                    }
                }
            }
        } else {
            // A reach larger than the grid itself: every cell is a candidate.
            for ids in self.grid.values() {
                for &(b, i) in ids {
                    consider(b, i, &mut out);
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Params;

    /// A bent branch of radius 1 and round cones across it, some holding
    /// parts of its contours, some all of them, some none.
    fn branch_and_cones() -> (Track, Vec<RoundCone>) {
        let points: Vec<DVec3> = (0..8)
            .map(|i| {
                let t = f64::from(i);
                DVec3::new(3.0 * t, 0.4 * t * t, 0.0)
            })
            .collect();
        let track = Track::new(&points, &[1.0; 8], &Params::DEFAULT, None);
        let mut cones: Vec<RoundCone> = Vec::new();
        for k in 0..12 {
            let t = f64::from(k);
            let a = DVec3::new(
                2.0 * t - 1.0,
                0.3 * t * t - 1.5 + 0.3 * (t * 1.7).sin(),
                0.5,
            );
            let b = a + DVec3::new(1.5, 2.0 + 0.2 * t, -1.0);
            cones.push(RoundCone {
                a,
                ra: 0.4 + 0.15 * t,
                b,
                rb: 1.6 - 0.1 * t,
            });
        }
        (track, cones)
    }

    #[test]
    fn the_fraction_outside_does_not_depend_on_the_hint() {
        let (track, cones) = branch_and_cones();
        let mut partly = 0;
        let mut carried = None;
        for i in 0..track.samples.len() {
            let alone = fraction_outside(&track, i, &cones, &mut None);
            partly += usize::from(alone > 0.0 && alone < 1.0);
            for &c in &cones {
                assert_eq!(fraction_outside(&track, i, &cones, &mut Some(c)), alone);
            }
            // As span and segment_gains carry it from contour to contour.
            assert_eq!(fraction_outside(&track, i, &cones, &mut carried), alone);
        }
        assert!(partly > 2, "some contours are partly held: {partly}");
        assert!(carried.is_some(), "a cone held some vertex");
    }

    #[test]
    fn the_first_contour_outside_does_not_depend_on_the_cones_order() {
        let (track, cones) = branch_and_cones();
        let mut reversed = cones.clone();
        reversed.reverse();
        for from in 0..track.samples.len() {
            assert_eq!(
                first_outside_from(&track, from, &cones),
                first_outside_from(&track, from, &reversed)
            );
        }
        assert!(first_outside(&track, &cones).is_some_and(|k| k > 0));
    }
}
