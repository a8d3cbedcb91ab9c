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
//! * **Volume**: points uniform inside `i` that lie in no primitive of lower
//!   index partition the union: `V = Σ V_i · (fraction outside all j < i)`.
//!
//! With the default number of samples the relative standard error is about
//! 0.2 %; results are identical from run to run.

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

/// Surface samples over the whole union (volume samples likewise).
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

    fn aabb(&self) -> Aabb {
        let r = DVec3::splat(self.ra.max(self.rb));
        Aabb::of(&[
            (self.a.min(self.b) - r).to_array(),
            (self.a.max(self.b) + r).to_array(),
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
    let cones: Vec<RoundCone> = cones.iter().map(|c| c.normalised()).collect();
    if cones.is_empty() {
        return UnionMeasures::default();
    }
    // Which primitives may contain a point of a given one: box overlaps.
    let boxes: Vec<Aabb> = cones.iter().map(RoundCone::aabb).collect();
    let bvh = Bvh::new(boxes.clone());
    let parts: Vec<([f64; 3], f64, f64)> = cones.iter().map(RoundCone::parts).collect();
    let total_area: f64 = parts.iter().map(|p| p.0.iter().sum::<f64>()).sum();
    let total_volume: f64 = parts.iter().map(|p| p.1).sum();
    let scale = cones
        .iter()
        .map(|c| c.ra.max(c.rb))
        .fold(0.0, f64::max)
        .max(1e-300);
    let eps = 1e-9 * scale;
    let per_cone: Vec<(f64, f64)> = crate::parallel::flat_map_range(cones.len(), |i| {
        let mut rng = Rng::new(0x5EED ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let c = &cones[i];
        let (areas, volume, sin) = parts[i];
        let (e1, e2, u, d) = frame(c);
        let mut near = Vec::new();
        bvh.for_each_overlap(&boxes[i], |j| {
            if j as usize != i {
                near.push(j);
            }
        });
        // Area: each part sampled in proportion to its area.
        let mut area = 0.0;
        for (part, &a_part) in areas.iter().enumerate() {
            if a_part <= 0.0 {
                continue;
            }
            let n = samples_for(a_part, total_area);
            let mut outside = 0usize;
            for _ in 0..n {
                let p = surface_point(c, part, sin, (e1, e2, u, d), &mut rng);
                let covered = near.iter().any(|&j| {
                    let s = cones[j as usize].sdf(p);
                    s < -eps || (s <= eps && (j as usize) < i)
                });
                outside += usize::from(!covered);
            }
            area += a_part * outside as f64 / n as f64;
        }
        // Volume: uniform points inside, by rejection from a bounding cylinder.
        let n = samples_for(volume, total_volume);
        let mut kept = 0usize;
        let mut drawn = 0usize;
        let rmax = c.ra.max(c.rb);
        while drawn < n {
            let x = -c.ra + rng.next() * (d + c.ra + c.rb);
            let rho = rmax * rng.next().sqrt();
            let th = std::f64::consts::TAU * rng.next();
            let p = c.a + u * x + rho * (th.cos() * e1 + th.sin() * e2);
            if c.sdf(p) > 0.0 {
                continue;
            }
            drawn += 1;
            let covered = near
                .iter()
                .any(|&j| (j as usize) < i && cones[j as usize].sdf(p) <= 0.0);
            kept += usize::from(!covered);
        }
        vec![(area, volume * kept as f64 / n as f64)]
    });
    UnionMeasures {
        area: per_cone.iter().map(|p| p.0).sum(),
        volume: per_cone.iter().map(|p| p.1).sum(),
    }
}

fn samples_for(part: f64, total: f64) -> usize {
    ((SAMPLES as f64 * part / total).ceil() as usize).clamp(2, SAMPLES)
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
