//! The round cone: the convex hull of two spheres, the primitive of the
//! skeleton's volume. Each segment (parent, child) of a morphology is one
//! (the union of the spheres centred along the segment with linearly
//! interpolated radii), a soma or a lone root is a sphere, and the union of
//! them all is the shape a membrane mesh stands for.

use glam::DVec3;

use super::bvh::Aabb;

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
    pub fn normalised(self) -> RoundCone {
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

    /// Whether it is a sphere (both ends at one point).
    pub fn is_sphere(&self) -> bool {
        self.a == self.b
    }

    /// Signed distance-like value: negative inside, zero on the surface (the
    /// true distance outside the lateral part and the caps).
    pub fn sdf(&self, p: DVec3) -> f64 {
        self.sdf_and_radius(p).0
    }

    /// [`RoundCone::sdf`], and the radius of the cone's sphere that attains
    /// it (the sphere along the axis nearest to `p` in that sense): the local
    /// radius a distance from the cone is measured in.
    pub fn sdf_and_radius(&self, p: DVec3) -> (f64, f64) {
        let ab = self.b - self.a;
        let d = ab.length();
        if d == 0.0 {
            let r = self.ra.max(self.rb);
            return (p.distance(self.a) - r, r);
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
        let r = self.ra - k * s;
        (((x - s).powi(2) + y * y).sqrt() - r, r)
    }

    /// Exact surface area and volume, and the parts' areas for sampling:
    /// (cap at a, lateral, cap at b), with `sin φ` of the tangent cone.
    pub fn parts(&self) -> ([f64; 3], f64, f64) {
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
