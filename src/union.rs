//! Area and volume of the exact union of the skeleton's round cones: the
//! reference a mesh of the membrane is measured against.
//!
//! Each segment (parent, child) is a *round cone*: the convex hull of the two
//! samples' spheres, which is also the union of the spheres centred along the
//! segment with linearly interpolated radii. A soma is one sphere (centre and
//! NeuroM radius, see [`crate::morphology::Soma`]); segments between two soma
//! samples are left out, segments from a soma sample to a neurite are kept.
//!
//! The union has no closed form, so it is integrated by seeded Monte Carlo
//! over each primitive's own surface and volume, whose measures are exact:
//!
//! * **Area**: points uniform on primitive `i`'s surface that lie strictly
//!   inside no other primitive are on the union's boundary, so the union's
//!   area is `Σ A_i · (fraction of i's points outside all others)`. Where two
//!   primitives share a piece of surface (consecutive cones share their joint's
//!   sphere) a point on both counts for the lower index only.
//! * **Volume**: a point uniform inside `i` is weighted by one over the
//!   number of primitives holding it, so that `V = Σ V_i · (mean weight)`.
//!
//! Three things keep the estimate precise where primitives pile up, as on
//! the blob cells ([`crate::blob`]), whose unions are hundreds of nearly
//! concentric spheres:
//!
//! * Primitives that another single primitive contains are left out first
//!   (they add nothing): two thirds of the cones of a blob cell.
//! * The volume's weights: counting only the points in no primitive of lower
//!   index has the same mean, but where hundreds of primitives overlap nearly
//!   every point counts zero and the rare ones decide.
//! * The surface points come in two rounds. A pilot spreads them in
//!   proportion to each part's area; the main round, the only one counted,
//!   in proportion to the area times the standard deviation of the pilot's
//!   hit rate (Neyman allocation), so buried parts get few points and
//!   exposed ones many. The primitives are ordered largest first, so the
//!   tests stop at the first (largest) primitive that covers a point.
//!
//! Over three seeds, the estimates spread (largest less smallest, over the
//! mean) by 0.5 % in area and 0.2 % in volume on the fly larva A00b, an
//! ordinary cell. The blob cells stay unsure in area: 14 % on the
//! 66,578-sample CAR cell (60 % before these steps) and 4 % on CAR 00148
//! (10 %); in volume 2.1 % (9 %) and 0.1 % (1.5 %). Results are identical
//! from run to run. With twenty times the points, CAR 00148's area came
//! within 0.21 % of its mesh's, a radial graph over its exactly
//! star-shaped union ([`crate::blob`]); the mesh is 4.86 % over the
//! estimate at the default budget, which stays because that run took 89 s
//! (CAR 66k's, 31 minutes).

use glam::DVec3;

use crate::bvh::{Aabb, Bvh};
use crate::morphology::{Morphology, NO_PARENT};

/// A round cone; a sphere when `a == b` (or when one end's sphere contains
/// the other).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoundCone {
    /// One end and its radius.
    pub a: DVec3,
    /// Radius at `a`.
    pub ra: f64,
    /// Other end.
    pub b: DVec3,
    /// Radius at `b`.
    pub rb: f64,
}

/// The union's measures.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct UnionMeasures {
    /// Area of the union's boundary.
    pub area: f64,
    /// Volume of the union.
    pub volume: f64,
}

/// Surface points of the pilot round, which sets how the main round's are
/// spread.
const PILOT: usize = 100_000;
/// Surface points of the main round, and volume points, over the whole union.
const SAMPLES: usize = 200_000;

impl RoundCone {
    /// A sphere.
    pub fn sphere(c: DVec3, r: f64) -> RoundCone {
        RoundCone {
            a: c,
            ra: r,
            b: c,
            rb: r,
        }
    }

    /// The same shape with the larger sphere first, or a sphere if one end's
    /// sphere contains the other's.
    fn normalised(self) -> RoundCone {
        let d = self.a.distance(self.b);
        if d + self.ra.min(self.rb) <= self.ra.max(self.rb) {
            return if self.ra >= self.rb {
                RoundCone::sphere(self.a, self.ra)
            } else {
                RoundCone::sphere(self.b, self.rb)
            };
        }
        self
    }

    fn is_sphere(&self) -> bool {
        self.a == self.b
    }

    /// Signed distance-like value: negative inside, zero on the surface (the
    /// true distance outside the lateral part and the caps).
    pub fn sdf(&self, p: DVec3) -> f64 {
        let ab = self.b - self.a;
        let d = ab.length();
        if d == 0.0 {
            return p.distance(self.a) - self.ra.max(self.rb);
        }
        let u = ab / d;
        let x = (p - self.a).dot(u);
        let y = (p - self.a - u * x).length();
        // Minimise |p − q(s)| − r(s) over s in [0, d] (convex in s).
        let k = (self.ra - self.rb) / d;
        let s = if k.abs() < 1.0 {
            (x - k * y / (1.0 - k * k).sqrt()).clamp(0.0, d)
        } else if k > 0.0 {
            0.0
        } else {
            d
        };
        ((x - s).powi(2) + y * y).sqrt() - (self.ra - k * s)
    }

    /// Exact surface area and volume, and the parts' areas for sampling:
    /// (cap at a, lateral, cap at b), with `sin φ` of the tangent cone.
    fn parts(&self) -> ([f64; 3], f64, f64) {
        use std::f64::consts::PI;
        if self.is_sphere() {
            let r = self.ra;
            return (
                [4.0 * PI * r * r, 0.0, 0.0],
                4.0 / 3.0 * PI * r * r * r,
                0.0,
            );
        }
        let d = self.a.distance(self.b);
        let (ra, rb) = (self.ra, self.rb);
        let sin = (ra - rb) / d;
        let cos = (1.0 - sin * sin).max(0.0).sqrt();
        let (ha, hb) = (ra * (1.0 + sin), rb * (1.0 - sin));
        let cap_a = 2.0 * PI * ra * ha;
        let cap_b = 2.0 * PI * rb * hb;
        let (pa, pb) = (ra * cos, rb * cos);
        let lateral = PI * (pa + pb) * d * cos;
        let cap_volume = |r: f64, h: f64| PI * h * h * (3.0 * r - h) / 3.0;
        let frustum = PI * d * cos * cos * (pa * pa + pa * pb + pb * pb) / 3.0;
        (
            [cap_a, lateral, cap_b],
            cap_volume(ra, ha) + frustum + cap_volume(rb, hb),
            sin,
        )
    }

    /// The box of the two end spheres, which is the cone's own: the
    /// extent of a convex hull in any direction is its parts' largest.
    pub fn aabb(&self) -> Aabb {
        let (ra, rb) = (DVec3::splat(self.ra), DVec3::splat(self.rb));
        Aabb::of(&[
            (self.a - ra).min(self.b - rb).to_array(),
            (self.a + ra).max(self.b + rb).to_array(),
        ])
    }
}

/// The primitives of a morphology: one sphere per soma, one round cone per
/// segment not between two soma samples (a lone root is a sphere).
pub fn skeleton_primitives(m: &Morphology) -> Vec<RoundCone> {
    labelled_primitives(m).map(|(c, _)| c).collect()
}

/// [`skeleton_primitives`] one at a time, each with the sample it stands
/// for: a soma's first sample, else the child end of the segment (or the
/// lone root). Nothing is allocated beyond the soma mask.
pub fn labelled_primitives(m: &Morphology) -> impl Iterator<Item = (RoundCone, u32)> + '_ {
    let (pos, r, parents) = (m.positions(), m.radii(), m.parents());
    let soma = m.soma_mask();
    let v = |i: usize| DVec3::from_array(pos[i]);
    let somas = m.trees().iter().filter_map(|t| t.soma.as_ref()).map(|s| {
        (
            RoundCone::sphere(DVec3::from_array(s.center), s.radius),
            s.samples.first().copied().unwrap_or(0),
        )
    });
    let segments = (0..m.len()).filter_map(move |i| {
        let p = parents[i];
        let cone = if p == NO_PARENT {
            (!soma[i]).then(|| RoundCone::sphere(v(i), r[i]))
        } else {
            (!(soma[i] && soma[p as usize])).then(|| RoundCone {
                a: v(p as usize),
                ra: r[p as usize],
                b: v(i),
                rb: r[i],
            })
        };
        cone.map(|c| (c, i as u32))
    });
    somas.chain(segments)
}

/// Measures of the union of the morphology's round cones.
pub fn measure_morphology(m: &Morphology) -> UnionMeasures {
    measure(&skeleton_primitives(m))
}

/// Measures of the union of `cones` (see the module documentation).
pub fn measure(cones: &[RoundCone]) -> UnionMeasures {
    let cones = exposed(cones);
    if cones.is_empty() {
        return UnionMeasures::default();
    }
    let sampler = Sampler::new(&cones);
    // Each primitive's three surface parts and its volume, measured exactly.
    let sizes: Vec<[f64; 4]> = sampler
        .parts
        .iter()
        .map(|&(a, v, _)| [a[0], a[1], a[2], v])
        .collect();
    let totals = sizes
        .iter()
        .fold([0.0; 2], |t, s| [t[0] + s[0] + s[1] + s[2], t[1] + s[3]]);
    let total_of = |k: usize| totals[usize::from(k == 3)];
    // The pilot: points on the surface in proportion to each part's area.
    let pilot: Vec<[u32; 4]> = sizes
        .iter()
        .map(|s| {
            std::array::from_fn(|k| {
                if k == 3 {
                    0
                } else {
                    samples_for(s[k], total_of(k), PILOT)
                }
            })
        })
        .collect();
    let pilot_hits =
        crate::parallel::flat_map_range(cones.len(), |i| vec![sampler.hits(i, pilot[i], 1)]);
    // Neyman allocation: the surface points go where the product of a part's
    // area and the standard deviation of its hit rate is large. On an
    // ordinary cell that is about in proportion to the area; on a blob cell,
    // whose primitives lie nearly all inside others, it is the few that show.
    // The volume points stay in proportion to the volumes (their weights do
    // not vary as much as hits do).
    let spread: Vec<[f64; 4]> = (0..cones.len())
        .map(|i| {
            std::array::from_fn(|k| {
                let f = (pilot_hits[i][k] + 0.5) / (f64::from(pilot[i][k]) + 1.0);
                sizes[i][k] * (f * (1.0 - f)).sqrt()
            })
        })
        .collect();
    let spread_total: f64 = spread.iter().map(|s| s[0] + s[1] + s[2]).sum();
    let main: Vec<[u32; 4]> = spread
        .iter()
        .zip(&sizes)
        .map(|(s, size)| {
            let mut n: [u32; 4] = std::array::from_fn(|k| samples_for(s[k], spread_total, SAMPLES));
            n[3] = samples_for(size[3], totals[1], SAMPLES);
            n
        })
        .collect();
    // Only the main points are counted: the pilot's chose their number, so
    // pooling them would bias the estimate.
    let per_cone = crate::parallel::flat_map_range(cones.len(), |i| {
        let hits = sampler.hits(i, main[i], 2);
        let part = |k: usize| {
            if main[i][k] == 0 {
                0.0
            } else {
                sizes[i][k] * hits[k] / f64::from(main[i][k])
            }
        };
        vec![(part(0) + part(1) + part(2), part(3))]
    });
    UnionMeasures {
        area: per_cone.iter().map(|p| p.0).sum(),
        volume: per_cone.iter().map(|p| p.1).sum(),
    }
}

/// Random points on and in the primitives, and which of them count.
struct Sampler<'a> {
    cones: &'a [RoundCone],
    boxes: Vec<Aabb>,
    bvh: Bvh,
    /// [`RoundCone::parts`] of each primitive.
    parts: Vec<([f64; 3], f64, f64)>,
    /// Distance under which a surface point counts as on another surface.
    eps: f64,
}

impl<'a> Sampler<'a> {
    fn new(cones: &'a [RoundCone]) -> Sampler<'a> {
        // Which primitives may contain a point of a given one: box overlaps.
        let boxes: Vec<Aabb> = cones.iter().map(RoundCone::aabb).collect();
        let bvh = Bvh::new(boxes.clone());
        let scale = cones
            .iter()
            .map(|c| c.ra.max(c.rb))
            .fold(0.0, f64::max)
            .max(1e-300);
        Sampler {
            cones,
            boxes,
            bvh,
            parts: cones.iter().map(RoundCone::parts).collect(),
            eps: 1e-9 * scale,
        }
    }

    /// Of `n[k]` random points on part `k` of primitive `i` (`k` < 3: cap at
    /// a, lateral, cap at b), how many count: those strictly inside no other
    /// primitive (a point on two surfaces counts for the lower index); and of
    /// `n[3]` random points inside it, the sum of their weights, one over the
    /// number of primitives that hold each. Round `round` draws its own
    /// points.
    fn hits(&self, i: usize, n: [u32; 4], round: u64) -> [f64; 4] {
        let cones = self.cones;
        let mut rng = Rng::new(
            0x5EED
                ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
                ^ round.wrapping_mul(0xD1B5_4A32_D192_ED03),
        );
        let c = &cones[i];
        let (_, _, sin) = self.parts[i];
        let (e1, e2, u, d) = frame(c);
        let mut near = Vec::new();
        self.bvh.for_each_overlap(&self.boxes[i], |j| {
            if j as usize != i {
                near.push(j);
            }
        });
        // Larger primitives first (the order of the indices): they cover most
        // points, so the tests below stop early.
        near.sort_unstable();
        let mut hits = [0.0; 4];
        for part in 0..3 {
            for _ in 0..n[part] {
                let p = surface_point(c, part, sin, (e1, e2, u, d), &mut rng);
                let covered = near.iter().any(|&j| {
                    let near_box = self.boxes[j as usize].inflated(self.eps);
                    if !near_box.holds_point(p.to_array()) {
                        return false;
                    }
                    let s = cones[j as usize].sdf(p);
                    s < -self.eps || (s <= self.eps && (j as usize) < i)
                });
                hits[part] += f64::from(u8::from(!covered));
            }
        }
        // Volume: uniform points inside, by rejection from a bounding
        // cylinder, each weighted by one over the number of primitives that
        // hold it. Counting the points in no primitive of lower index instead
        // has the same mean, but where hundreds of primitives overlap (the
        // blob cells) nearly every point counts zero and the rare ones decide.
        let rmax = c.ra.max(c.rb);
        let mut drawn = 0;
        while drawn < n[3] {
            let x = -c.ra + rng.next() * (d + c.ra + c.rb);
            let rho = rmax * rng.next().sqrt();
            let th = std::f64::consts::TAU * rng.next();
            let p = c.a + u * x + rho * (th.cos() * e1 + th.sin() * e2);
            if c.sdf(p) > 0.0 {
                continue;
            }
            drawn += 1;
            let holders = 1 + near
                .iter()
                .filter(|&&j| {
                    self.boxes[j as usize].holds_point(p.to_array())
                        && cones[j as usize].sdf(p) <= 0.0
                })
                .count();
            hits[3] += 1.0 / holders as f64;
        }
        hits
    }
}

/// The primitives (normalised) that no other single primitive contains.
///
/// A round cone is the convex hull of its end spheres, so it lies inside a
/// convex primitive that holds both of them; a sphere is held when its
/// centre is at least its radius inside (the `sdf` is never deeper than the
/// true distance to the surface, so the test is safe). Of two equal
/// primitives the first is kept. Those left out add nothing to the union's
/// area or volume, and leaving them out matters where sample points are
/// scarce: on the blob cells (radius codes) two thirds of the cones lie
/// inside the largest sphere and took two thirds of the samples.
fn exposed(cones: &[RoundCone]) -> Vec<RoundCone> {
    // Largest first (a stable sort, so equal volumes keep their order): see
    // `measure`.
    let mut by_volume: Vec<(f64, RoundCone)> = cones
        .iter()
        .map(|c| {
            let c = c.normalised();
            (c.parts().1, c)
        })
        .collect();
    by_volume.sort_by(|a, b| b.0.total_cmp(&a.0));
    let cones: Vec<RoundCone> = by_volume.into_iter().map(|(_, c)| c).collect();
    let boxes: Vec<Aabb> = cones.iter().map(RoundCone::aabb).collect();
    let bvh = Bvh::new(boxes.clone());
    let holds = |outer: &RoundCone, inner: &RoundCone| {
        outer.sdf(inner.a) + inner.ra <= 0.0 && outer.sdf(inner.b) + inner.rb <= 0.0
    };
    crate::parallel::flat_map_range(cones.len(), |i| {
        let c = &cones[i];
        let mut held = false;
        // A primitive that holds another has at least its volume, so it
        // comes first; of equal ones the first holds the others.
        bvh.for_each_containing(&boxes[i], |j| {
            held = held || ((j as usize) < i && holds(&cones[j as usize], c));
        });
        Vec::from_iter((!held).then_some(*c))
    })
}

/// Points for a part of measure `part` out of `total`, from a budget of
/// `budget` (at least 2 for a part of positive measure, none for a part of
/// measure zero).
fn samples_for(part: f64, total: f64, budget: usize) -> u32 {
    if part <= 0.0 {
        return 0;
    }
    ((budget as f64 * part / total).ceil() as usize).clamp(2, budget) as u32
}

/// Orthonormal frame along the cone's axis, and its length.
fn frame(c: &RoundCone) -> (DVec3, DVec3, DVec3, f64) {
    let ab = c.b - c.a;
    let d = ab.length();
    let u = if d > 0.0 { ab / d } else { DVec3::Z };
    let e1 = crate::contour::any_perpendicular(u);
    (e1, u.cross(e1), u, d)
}

/// A point uniform on part `part` (0: cap at a, 1: lateral, 2: cap at b).
fn surface_point(
    c: &RoundCone,
    part: usize,
    sin: f64,
    (e1, e2, u, d): (DVec3, DVec3, DVec3, f64),
    rng: &mut Rng,
) -> DVec3 {
    let th = std::f64::consts::TAU * rng.next();
    let around = th.cos() * e1 + th.sin() * e2;
    let on_sphere = |center: DVec3, r: f64, z: f64| {
        // Archimedes: the axial coordinate of a uniform point is uniform.
        center + u * z + around * (r * r - z * z).max(0.0).sqrt()
    };
    if c.is_sphere() {
        return on_sphere(c.a, c.ra, c.ra * (2.0 * rng.next() - 1.0));
    }
    match part {
        0 => on_sphere(c.a, c.ra, -c.ra + rng.next() * c.ra * (1.0 + sin)),
        2 => on_sphere(c.b, c.rb, c.rb * sin + rng.next() * c.rb * (1.0 - sin)),
        _ => {
            // Lateral: radius linear along the slant, density ∝ radius.
            let cos = (1.0 - sin * sin).max(0.0).sqrt();
            let (pa, pb) = (c.ra * cos, c.rb * cos);
            let w = rng.next();
            let s = if (pa - pb).abs() < 1e-12 * pa.max(pb) {
                w
            } else {
                // Inverse of the CDF ∝ pa·s + (pb − pa)·s²/2.
                let (qa, qb) = (pa * pa, pb * pb);
                ((qa + w * (qb - qa)).sqrt() - pa) / (pb - pa)
            };
            let (xa, xb) = (c.ra * sin, d + c.rb * sin);
            c.a + u * (xa + s * (xb - xa)) + around * (pa + s * (pb - pa))
        }
    }
}

/// xorshift64*: small, seeded, good enough for integration.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(seed.max(1))
    }
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn close(got: f64, want: f64, tol: f64) {
        assert!((got / want - 1.0).abs() < tol, "{got} against {want}");
    }

    #[test]
    fn one_sphere_is_exact() {
        let m = measure(&[RoundCone::sphere(DVec3::ONE, 2.0)]);
        close(m.area, 16.0 * PI, 1e-12);
        close(m.volume, 32.0 / 3.0 * PI, 1e-12);
    }

    #[test]
    fn capsule_as_two_touching_cones() {
        // A capsule of radius 1 and length 10, split in two cones at x = 4.
        let a = RoundCone {
            a: DVec3::ZERO,
            ra: 1.0,
            b: DVec3::new(4.0, 0.0, 0.0),
            rb: 1.0,
        };
        let b = RoundCone {
            a: DVec3::new(4.0, 0.0, 0.0),
            ra: 1.0,
            b: DVec3::new(10.0, 0.0, 0.0),
            rb: 1.0,
        };
        let m = measure(&[a, b]);
        close(m.area, 2.0 * PI * 10.0 + 4.0 * PI, 0.005);
        close(m.volume, PI * 10.0 + 4.0 / 3.0 * PI, 0.005);
    }

    #[test]
    fn round_cone_measures_match_a_fine_revolution() {
        // Exact parts against the union of many thin spheres along the axis.
        let c = RoundCone {
            a: DVec3::ZERO,
            ra: 2.0,
            b: DVec3::new(5.0, 0.0, 0.0),
            rb: 0.5,
        };
        let (areas, volume, _) = c.parts();
        // Profile of the convex hull of the two spheres, integrated numerically.
        let sin: f64 = (2.0 - 0.5) / 5.0;
        let cos = (1.0 - sin * sin).sqrt();
        let (xa, xb) = (2.0 * sin, 5.0 + 0.5 * sin);
        let radius = |x: f64| {
            if x < xa {
                (4.0 - x * x).max(0.0).sqrt()
            } else if x > xb {
                (0.25 - (x - 5.0).powi(2)).max(0.0).sqrt()
            } else {
                2.0 * cos + (x - xa) / (xb - xa) * (0.5 * cos - 2.0 * cos)
            }
        };
        let n = 200_000;
        let (lo, hi) = (-2.0, 5.5);
        let h = (hi - lo) / n as f64;
        let vol: f64 = (0..n)
            .map(|k| PI * radius(lo + (k as f64 + 0.5) * h).powi(2) * h)
            .sum();
        close(volume, vol, 1e-4);
        assert!(areas.iter().all(|&a| a > 0.0));
    }

    #[test]
    fn nested_sphere_adds_nothing() {
        let m = measure(&[
            RoundCone::sphere(DVec3::ZERO, 3.0),
            RoundCone::sphere(DVec3::new(0.5, 0.0, 0.0), 1.0),
        ]);
        close(m.area, 36.0 * PI, 1e-9);
        close(m.volume, 36.0 * PI, 1e-9);
    }

    /// Two spheres whose union has a closed form, under hundreds of round
    /// cones nested in the larger one (as on the blob cells, where most
    /// primitives lie inside others): the nested ones are left out before
    /// sampling and the estimate keeps its precision.
    #[test]
    fn nested_cones_leave_two_overlapping_spheres_exact() {
        let (big, small, d) = (10.0, 3.0, 10.0);
        let mut cones = vec![
            RoundCone::sphere(DVec3::ZERO, big),
            RoundCone::sphere(DVec3::new(d, 0.0, 0.0), small),
        ];
        let mut rng = Rng::new(7);
        for _ in 0..400 {
            let mut at = || DVec3::new(rng.next(), rng.next(), rng.next()) * 8.0 - 4.0;
            let (a, b) = (at(), at());
            cones.push(RoundCone {
                a,
                ra: 1.0 + rng.next(),
                b,
                rb: 0.5,
            });
        }
        // The second sphere twice: equal primitives keep one copy.
        cones.push(cones[1]);
        assert_eq!(exposed(&cones).len(), 2);
        // The caps each sphere has inside the other.
        let h_big = (small - big + d) * (small + big - d) / (2.0 * d);
        let h_small = (big - small + d) * (big + small - d) / (2.0 * d);
        let area =
            4.0 * PI * (big * big + small * small) - 2.0 * PI * (big * h_big + small * h_small);
        let lens = PI
            * (big + small - d).powi(2)
            * (d * d + 2.0 * d * small - 3.0 * small * small + 2.0 * d * big + 6.0 * small * big
                - 3.0 * big * big)
            / (12.0 * d);
        let volume = 4.0 / 3.0 * PI * (big.powi(3) + small.powi(3)) - lens;
        let m = measure(&cones);
        close(m.area, area, 0.005);
        close(m.volume, volume, 0.005);
    }

    #[test]
    fn sdf_signs() {
        let c = RoundCone {
            a: DVec3::ZERO,
            ra: 2.0,
            b: DVec3::new(5.0, 0.0, 0.0),
            rb: 0.5,
        };
        assert!(c.sdf(DVec3::new(2.0, 0.0, 0.0)) < 0.0);
        assert!(c.sdf(DVec3::new(2.0, 3.0, 0.0)) > 0.0);
        assert!((c.sdf(DVec3::new(-2.0, 0.0, 0.0))).abs() < 1e-12);
        assert!((c.sdf(DVec3::new(5.5, 0.0, 0.0))).abs() < 1e-12);
    }
}
