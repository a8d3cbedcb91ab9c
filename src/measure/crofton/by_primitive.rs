//! Lines through each primitive, for ordinary cells.
//!
//! The lines meeting a convex body `K` have measure `A(K) / 4` (its mean
//! projected area), and drawing one uniformly among them is easy: a uniform
//! direction, then a foot uniform over `K`'s shadow (by rejection from a
//! rectangle around it). Along a line, the union is a few disjoint pieces;
//! the piece through primitive `i` is made of the intervals of `h`
//! primitives, each of which draws this line as often, so weighting it by
//! `1 / h` counts it once. A piece has two boundary crossings and a length
//! `ℓ`, hence
//!
//! ```text
//! A = Σ_i A_i / 2 · E_i[2 / h]        V = Σ_i A_i / 4 · E_i[ℓ / h]
//! ```
//!
//! A primitive that no other meets contributes exactly its area. Only the
//! piece through `i` is followed, so a line's cost is its neighbourhood's,
//! not the whole cell's.

use glam::DVec3;

use super::intervals::line_interval;
use super::strata::{PILOT, Tally, allocate, stream, totals};
use crate::kernel::bvh::Bvh;
use crate::kernel::rng::Rng;
use crate::kernel::round_cone::RoundCone;

/// Lines drawn from every primitive by the scout, and at least from each
/// in the main round.
const MIN_LINES: u32 = 4;

/// Area and volume of the union of `cones`, with up to `lines` lines in the
/// main round.
pub(super) fn measure(cones: &[RoundCone], lines: usize, seed: u64) -> (f64, f64) {
    let areas: Vec<f64> = cones.iter().map(|c| c.parts().0.iter().sum()).collect();
    let total: f64 = areas.iter().sum();
    if total <= 0.0 {
        return (0.0, 0.0);
    }
    let bvh = Bvh::new(cones.iter().map(RoundCone::aabb).collect());
    let scout = tally(&bvh, cones, &areas, &vec![MIN_LINES; cones.len()], seed);
    let by_area: Vec<u32> = areas
        .iter()
        .map(|a| (PILOT as f64 * a / total).ceil() as u32)
        .collect();
    let mut pilot = tally(&bvh, cones, &areas, &by_area, seed ^ 0x5EED_0001);
    for (p, s) in pilot.iter_mut().zip(&scout) {
        p.merge(s);
    }
    let counts = allocate(&pilot, lines, MIN_LINES);
    totals(&tally(&bvh, cones, &areas, &counts, seed ^ 0x5EED_0002))
}

/// The mean number of intervals a line through a primitive costs, from one
/// line through each of up to `lines` primitives spread over the list.
pub(super) fn probe(cones: &[RoundCone], lines: usize) -> f64 {
    let bvh = Bvh::new(cones.iter().map(RoundCone::aabb).collect());
    let step = cones.len().div_ceil(lines).max(1);
    let mut spans = Vec::new();
    let (mut cost, mut drawn) = (0.0, 0.0);
    for i in (0..cones.len()).step_by(step) {
        let mut rng = stream(0x960BE, i);
        let (o, dir, own) = line_through(&cones[i], &mut rng);
        component(&bvh, cones, i, o, dir, own, &mut spans);
        cost += spans.len() as f64;
        drawn += 1.0;
    }
    cost / drawn
}

/// Draws `counts[i]` lines through each primitive `i`.
fn tally(bvh: &Bvh, cones: &[RoundCone], areas: &[f64], counts: &[u32], seed: u64) -> Vec<Tally> {
    crate::kernel::parallel::flat_map_range(cones.len(), |i| {
        let mut rng = stream(seed, i);
        let mut spans: Vec<(f64, f64)> = Vec::new();
        let mut t = Tally::default();
        for _ in 0..counts[i] {
            let (o, dir, own) = line_through(&cones[i], &mut rng);
            let (h, length) = component(bvh, cones, i, o, dir, own, &mut spans);
            t.area.add(areas[i] / h);
            t.volume.add(areas[i] / 4.0 * length / h);
            // A search of the tree weighs about as much as a few intervals.
            t.cost += spans.len() as f64 + 4.0;
        }
        vec![t]
    })
}

/// A line uniform among those that meet `c`: a point on it, its direction,
/// and the interval of `c` along it.
fn line_through(c: &RoundCone, rng: &mut Rng) -> (DVec3, DVec3, (f64, f64)) {
    let mid = 0.5 * (c.a + c.b);
    let rmax = c.ra.max(c.rb);
    let half = 0.5 * c.a.distance(c.b);
    loop {
        let z = 2.0 * rng.f64() - 1.0;
        let phi = std::f64::consts::TAU * rng.f64();
        let s = (1.0 - z * z).max(0.0).sqrt();
        let dir = DVec3::new(s * phi.cos(), s * phi.sin(), z);
        // The shadow lies in a rectangle along the projected axis, as long
        // as the whole axis and widened by the larger radius on every side.
        // Its area must not depend on the direction: the directions kept are
        // then in proportion to the shadow's area, as they should be.
        let axis = (c.b - c.a) - dir * (c.b - c.a).dot(dir);
        let e1 = if axis.length_squared() > 0.0 {
            axis.normalize()
        } else {
            crate::kernel::vector::any_perpendicular(dir)
        };
        let e2 = dir.cross(e1);
        let x = (2.0 * rng.f64() - 1.0) * (half + rmax);
        let y = (2.0 * rng.f64() - 1.0) * rmax;
        let o = mid + e1 * x + e2 * y;
        if let Some(span) = line_interval(c, o, dir) {
            return (o, dir, span);
        }
    }
}

/// The piece of the union along the line `o + t·dir` that holds primitive
/// `i`'s interval `own`: the number of primitives whose intervals make it up
/// and its length. The line is searched only as far as the piece reaches,
/// widening the search while the piece grows past it.
fn component(
    bvh: &Bvh,
    cones: &[RoundCone],
    i: usize,
    o: DVec3,
    dir: DVec3,
    own: (f64, f64),
    spans: &mut Vec<(f64, f64)>,
) -> (f64, f64) {
    let (mut lo, mut hi) = own;
    loop {
        spans.clear();
        let start = o + dir * lo;
        bvh.for_each_on_ray(start.to_array(), dir.to_array(), hi - lo, |j| {
            if j as usize == i {
                return;
            }
            if let Some(s) = line_interval(&cones[j as usize], o, dir) {
                spans.push(s);
            }
        });
        spans.push(own);
        let (count, piece) = piece_holding(spans, own.0);
        if piece.0 < lo || piece.1 > hi {
            (lo, hi) = (piece.0.min(lo), piece.1.max(hi));
            continue;
        }
        return (f64::from(count), piece.1 - piece.0);
    }
}

/// Sorts the intervals and returns the merged piece of their union that
/// holds `t` (which some interval holds), with the number of intervals in
/// it. Intervals that touch are one piece.
fn piece_holding(spans: &mut [(f64, f64)], t: f64) -> (u32, (f64, f64)) {
    spans.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    let mut count = 0;
    let mut current: Option<(f64, f64)> = None;
    for &(lo, hi) in spans.iter() {
        match current {
            Some((clo, chi)) if lo <= chi => {
                current = Some((clo, chi.max(hi)));
                count += 1;
            }
            Some(piece) if piece.0 <= t && t <= piece.1 => return (count, piece),
            _ => {
                current = Some((lo, hi));
                count = 1;
            }
        }
    }
    (count, current.expect("the own interval is among the spans"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_piece_holding_a_point_counts_its_intervals() {
        let mut spans = vec![(2.0, 3.0), (0.0, 1.0), (1.0, 2.0), (5.0, 6.5)];
        assert_eq!(piece_holding(&mut spans, 0.5), (3, (0.0, 3.0)));
        assert_eq!(piece_holding(&mut spans, 3.0), (3, (0.0, 3.0)));
        assert_eq!(piece_holding(&mut spans, 5.5), (1, (5.0, 6.5)));
    }
}
