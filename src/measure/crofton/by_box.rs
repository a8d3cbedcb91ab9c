//! Lines through boxes, for cells whose primitives pile up.
//!
//! Space is cut into disjoint boxes, so each boundary crossing and each
//! piece of length lies in one box and the measures are sums over boxes. A
//! box is halved across its longest side while more than [`LEAF`]
//! primitives reach into it or it is wide against its thinnest member (by
//! its larger radius); a
//! box that one primitive contains whole (all eight corners inside a convex
//! primitive) adds its volume exactly and no area, and a box no primitive
//! reaches adds nothing. Lines through the remaining boxes come from the
//! box's circumscribed sphere, of radius `R`: a uniform direction and a foot
//! uniform on the disc of radius `R` across it, so that within one box
//!
//! ```text
//! A_box = 2 π R² · E[n_box]        V_box = π R² · E[ℓ_box]
//! ```
//!
//! where `n_box` counts the union's boundary crossings strictly inside the
//! box and `ℓ_box` its length there, from the primitives that reach in.

use glam::DVec3;

use super::intervals::line_interval;
use super::strata::{PILOT, Tally, allocate, stream, totals};
use crate::kernel::rng::Rng;
use crate::kernel::round_cone::RoundCone;

/// Most primitives reaching into a box that is sampled rather than halved.
const LEAF: usize = 8;
/// Largest circumscribed radius of a sampled box, in radii of its thinnest
/// member.
const THIN: f64 = 2.0;
/// Circumscribed radius, in radii of the thinnest member, below which a
/// box is sampled however many primitives reach in (where hundreds of
/// spheres' surfaces nearly coincide, as on a blob cell's boundary).
const FINE: f64 = 0.5;
/// Halvings after which a box is sampled however many primitives reach in.
const MAX_DEPTH: u32 = 64;

/// A box to sample and the primitives that reach into it.
struct Cell {
    lo: DVec3,
    hi: DVec3,
    members: Vec<u32>,
}

/// Lines drawn through every box by the scout, and at least through each
/// in the main round.
const MIN_LINES: u32 = 8;

/// Area and volume of the union of `cones`, with up to `lines` lines in the
/// main round.
pub(super) fn measure(cones: &[RoundCone], lines: usize, seed: u64) -> (f64, f64) {
    let (cells, held) = partition(cones);
    if cells.is_empty() {
        return (0.0, held);
    }
    let scout = tally(cones, &cells, &vec![MIN_LINES; cells.len()], seed);
    // The pilot's lines beyond the scout's go by the boxes' discs, as many
    // as the cost budget allows at the scout's cost per line.
    let (cost, drawn) = scout
        .iter()
        .fold((0.0, 0.0), |(c, n), t| (c + t.cost, n + t.area.n));
    let extra = (PILOT as f64).min(PILOT as f64 * super::strata::COST_PER_LINE * drawn / cost);
    let discs: Vec<f64> = cells
        .iter()
        .map(|c| (c.hi - c.lo).length_squared())
        .collect();
    let total: f64 = discs.iter().sum();
    let by_disc: Vec<u32> = discs
        .iter()
        .map(|d| (extra * d / total).ceil() as u32)
        .collect();
    let mut pilot = tally(cones, &cells, &by_disc, seed ^ 0x5EED_0001);
    for (p, s) in pilot.iter_mut().zip(&scout) {
        p.merge(s);
    }
    let counts = allocate(&pilot, lines, MIN_LINES);
    let (area, volume) = totals(&tally(cones, &cells, &counts, seed ^ 0x5EED_0002));
    (area, volume + held)
}

/// Cuts the cones' bounding cube into the boxes to sample, and the volume
/// of the boxes that one primitive holds whole.
fn partition(cones: &[RoundCone]) -> (Vec<Cell>, f64) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for c in cones {
        let b = c.aabb();
        lo = lo.min(DVec3::from_array(b.lo));
        hi = hi.max(DVec3::from_array(b.hi));
    }
    // A cube, so that halving keeps the boxes near cubes.
    let side = (hi - lo).max_element();
    let hi = lo + DVec3::splat(side);
    let all: Vec<u32> = (0..cones.len() as u32).collect();
    let mut cells = Vec::new();
    let mut held = 0.0;
    split(cones, lo, hi, all, 0, &mut cells, &mut held);
    (cells, held)
}

fn split(
    cones: &[RoundCone],
    lo: DVec3,
    hi: DVec3,
    candidates: Vec<u32>,
    depth: u32,
    cells: &mut Vec<Cell>,
    held: &mut f64,
) {
    let centre = 0.5 * (lo + hi);
    let half = 0.5 * (hi - lo).length();
    let members: Vec<u32> = candidates
        .into_iter()
        .filter(|&j| reaches(&cones[j as usize], lo, hi, centre, half))
        .collect();
    if members.is_empty() {
        return;
    }
    if members.iter().any(|&j| holds(&cones[j as usize], lo, hi)) {
        let size = hi - lo;
        *held += size.x * size.y * size.z;
        return;
    }
    // Thin primitives in a large box are met by few of its lines, and the
    // rounds would miss them: boxes are halved down to their thinnest
    // member's scale too.
    let thinnest = members
        .iter()
        // A cone's larger radius: a cone may taper to a point.
        .map(|&j| cones[j as usize].ra.max(cones[j as usize].rb))
        .fold(f64::INFINITY, f64::min);
    if (members.len() <= LEAF && half <= THIN * thinnest)
        || half <= FINE * thinnest
        || depth >= MAX_DEPTH
    {
        cells.push(Cell { lo, hi, members });
        return;
    }
    let size = hi - lo;
    let axis = if size.x >= size.y && size.x >= size.z {
        0
    } else if size.y >= size.z {
        1
    } else {
        2
    };
    let mid = centre[axis];
    let (mut lower_hi, mut upper_lo) = (hi, lo);
    lower_hi[axis] = mid;
    upper_lo[axis] = mid;
    split(cones, lo, lower_hi, members.clone(), depth + 1, cells, held);
    split(cones, upper_lo, hi, members, depth + 1, cells, held);
}

/// Whether the primitive may reach into the box: their bounding boxes
/// overlap and the primitive comes within the box's circumscribed sphere.
fn reaches(c: &RoundCone, lo: DVec3, hi: DVec3, centre: DVec3, half: f64) -> bool {
    let b = c.aabb();
    let (blo, bhi) = (DVec3::from_array(b.lo), DVec3::from_array(b.hi));
    blo.cmple(hi).all() && lo.cmple(bhi).all() && c.sdf(centre) <= half
}

/// Whether the convex primitive contains the box: all its corners.
fn holds(c: &RoundCone, lo: DVec3, hi: DVec3) -> bool {
    let b = c.aabb();
    if !(DVec3::from_array(b.lo).cmple(lo).all() && hi.cmple(DVec3::from_array(b.hi)).all()) {
        return false;
    }
    (0..8).all(|k| {
        let corner = DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        c.sdf(corner) < 0.0
    })
}

/// Draws `counts[k]` lines through each box `k`.
fn tally(cones: &[RoundCone], cells: &[Cell], counts: &[u32], seed: u64) -> Vec<Tally> {
    crate::kernel::parallel::flat_map_range(cells.len(), |k| {
        let cell = &cells[k];
        let mut rng = stream(seed, k);
        let centre = 0.5 * (cell.lo + cell.hi);
        let radius = 0.5 * (cell.hi - cell.lo).length();
        let disc = std::f64::consts::PI * radius * radius;
        let mut spans: Vec<(f64, f64)> = Vec::with_capacity(cell.members.len());
        let mut t = Tally::default();
        for _ in 0..counts[k] {
            let (o, dir) = line_near(centre, radius, &mut rng);
            let (crossings, length) = match box_interval(cell.lo, cell.hi, o, dir) {
                Some(walls) => {
                    spans.clear();
                    spans.extend(
                        cell.members
                            .iter()
                            .filter_map(|&j| line_interval(&cones[j as usize], o, dir)),
                    );
                    within(&mut spans, walls)
                }
                None => (0, 0.0),
            };
            t.area.add(2.0 * disc * f64::from(crossings));
            t.cost += cell.members.len() as f64 + 4.0;
            t.volume.add(disc * length);
        }
        vec![t]
    })
}

/// A line uniform among those through the disc of radius `r` across a
/// uniform direction, centred at `c`: a point on it and its direction.
fn line_near(c: DVec3, r: f64, rng: &mut Rng) -> (DVec3, DVec3) {
    let z = 2.0 * rng.f64() - 1.0;
    let phi = std::f64::consts::TAU * rng.f64();
    let s = (1.0 - z * z).max(0.0).sqrt();
    let dir = DVec3::new(s * phi.cos(), s * phi.sin(), z);
    let e1 = crate::kernel::vector::any_perpendicular(dir);
    let e2 = dir.cross(e1);
    let rho = r * rng.f64().sqrt();
    let theta = std::f64::consts::TAU * rng.f64();
    (c + rho * (theta.cos() * e1 + theta.sin() * e2), dir)
}

/// The parameters where the line enters and leaves the box.
fn box_interval(lo: DVec3, hi: DVec3, o: DVec3, dir: DVec3) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for a in 0..3 {
        if dir[a].abs() < 1e-300 {
            if o[a] < lo[a] || o[a] > hi[a] {
                return None;
            }
            continue;
        }
        let (u, v) = ((lo[a] - o[a]) / dir[a], (hi[a] - o[a]) / dir[a]);
        t0 = t0.max(u.min(v));
        t1 = t1.min(u.max(v));
    }
    (t0 < t1).then_some((t0, t1))
}

/// The union of the intervals within `walls`: the number of its ends
/// strictly between the walls (boundary crossings inside the box) and its
/// length between them. Intervals that touch are one.
fn within(spans: &mut [(f64, f64)], walls: (f64, f64)) -> (u32, f64) {
    spans.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    let (w0, w1) = walls;
    let mut ends = 0;
    let mut length = 0.0;
    let mut flush = |lo: f64, hi: f64| {
        ends += u32::from(lo > w0 && lo < w1) + u32::from(hi > w0 && hi < w1);
        length += (hi.min(w1) - lo.max(w0)).max(0.0);
    };
    let mut current: Option<(f64, f64)> = None;
    for &(lo, hi) in spans.iter() {
        match current {
            Some((clo, chi)) if lo <= chi => current = Some((clo, chi.max(hi))),
            _ => {
                if let Some((clo, chi)) = current {
                    flush(clo, chi);
                }
                current = Some((lo, hi));
            }
        }
    }
    if let Some((clo, chi)) = current {
        flush(clo, chi);
    }
    (ends, length)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touching_intervals_are_one() {
        let mut spans = vec![(2.0, 3.0), (0.0, 1.0), (1.0, 2.0), (5.0, 6.5)];
        assert_eq!(within(&mut spans, (-1.0, 10.0)), (4, 4.5));
        // Ends on or past the walls are not crossings inside the box.
        assert_eq!(within(&mut spans, (0.0, 6.0)), (2, 4.0));
        assert_eq!(within(&mut spans, (0.5, 5.5)), (2, 3.0));
    }
}
