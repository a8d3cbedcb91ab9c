//! Contour frames (paper §3.2, Steps 1–3 and Fig. 3): the first-vertex
//! direction pushed forward from contour to contour, and the disc test that
//! decides which contours may follow which.
//!
//! The first vertex direction `u` of contour i+1 is `u_i` projected on the
//! plane of `o_{i+1}` and normalised; the other vertices follow by Rodrigues
//! rotation about `o_{i+1}` in steps of 2π/m (for `u ⟂ o` the rotation is
//! `cos θ u + sin θ (o × u)`). We carry `u` by the minimal rotation from `o_i`
//! to `o_{i+1}`, of which the projection is the first-order form (see
//! [`push_forward`]): a rotation-minimising frame, so first vertices
//! correspond from contour to contour without twist, even across the sharp
//! turns left where contours were skipped.
//!
//! A contour whose disc crosses the last kept contour's disc is skipped
//! ([`DiscFrame::clears`]); the next acceptable contour is connected to the
//! last kept one, so skipping never opens a hole.

use glam::DVec3;

use crate::kernel::vector::any_perpendicular;

/// Pushes the first-vertex direction `u` (⟂ `from`) onto the plane of `to`.
///
/// The paper projects `u` onto the new plane and normalises. That is the
/// first-order form of rotating `u` by the minimal rotation taking `from` to
/// `to`; the two agree for small turns, but at a sharp turn (tens of degrees
/// between kept contours) the projection compresses angles towards the rotation
/// axis and twists the band. We apply the rotation itself (Rodrigues' formula,
/// the paper's equation 2), which is exact at any angle.
pub fn push_forward(u: DVec3, from: DVec3, to: DVec3) -> DVec3 {
    let axis = from.cross(to);
    let s = axis.length();
    let c = from.dot(to);
    let rotated = if s > 1e-12 {
        let k = axis / s;
        u * c + k.cross(u) * s + k * k.dot(u) * (1.0 - c)
    } else if c < 0.0 {
        // Exactly reversed: any half-turn works; reflect through `u` itself.
        u
    } else {
        u
    };
    let fixed = rotated - rotated.dot(to) * to;
    if fixed.length_squared() > 1e-12 {
        fixed.normalize()
    } else {
        any_perpendicular(to)
    }
}

/// First-vertex directions for every tangent, by pushing forward from `u0`.
pub fn frames(tangents: impl ExactSizeIterator<Item = DVec3>, u0: DVec3) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(tangents.len());
    let mut u = u0;
    let mut last: Option<DVec3> = None;
    for t in tangents {
        if let Some(prev) = last {
            u = push_forward(u, prev, t);
        }
        out.push(u);
        last = Some(t);
    }
    out
}

/// The plane and disc of one contour, for the intersection test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscFrame {
    /// Centre.
    pub center: DVec3,
    /// Unit normal (tangent).
    pub normal: DVec3,
    /// Polygon radius.
    pub radius: f64,
}

impl DiscFrame {
    /// Whether `next` lies wholly in front of `self` and `self` wholly behind
    /// `next`, each by at least `margin`: then the band between the two contours
    /// cannot cross either of them.
    pub fn clears(&self, next: &DiscFrame, margin: f64) -> bool {
        let cos = self.normal.dot(next.normal).clamp(-1.0, 1.0);
        if cos <= 0.0 {
            return false;
        }
        let sin = (1.0 - cos * cos).sqrt();
        let d = next.center - self.center;
        let front = d.dot(self.normal) - next.radius * sin;
        let back = d.dot(next.normal) - self.radius * sin;
        front >= margin && back >= margin
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::vector::any_perpendicular;
    use crate::skeleton::spline::resample;

    #[test]
    fn frames_stay_orthonormal_and_untwisted_along_a_helix() {
        // A helix of radius 5 and pitch 2π·2, sampled densely.
        let pts: Vec<DVec3> = (0..400)
            .map(|i| {
                let t = f64::from(i) * 0.05;
                DVec3::new(5.0 * t.cos(), 5.0 * t.sin(), 2.0 * t)
            })
            .collect();
        let radii = vec![0.5; pts.len()];
        let s = resample(&pts, &radii, 0.5, 1);
        let u0 = any_perpendicular(s[0].tangent);
        let f = frames(s.iter().map(|x| x.tangent), u0);
        for (x, u) in s.iter().zip(&f) {
            assert!((u.length() - 1.0).abs() < 1e-9);
            assert!(u.dot(x.tangent).abs() < 1e-6);
        }
        // Rotation-minimising: consecutive u change only as much as the tangent turns.
        for i in 1..s.len() {
            let turn = s[i - 1].tangent.angle_between(s[i].tangent);
            let twist = f[i - 1].angle_between(f[i]);
            assert!(
                twist <= turn + 1e-6,
                "step {i}: u turned {twist} for a tangent turn of {turn}"
            );
        }
    }

    #[test]
    fn push_forward_survives_a_right_angle() {
        let u = push_forward(DVec3::Y, DVec3::X, DVec3::Y);
        assert!((u.length() - 1.0).abs() < 1e-12);
        assert!(u.dot(DVec3::Y).abs() < 1e-12);
    }

    #[test]
    fn disc_clearance() {
        let a = DiscFrame {
            center: DVec3::ZERO,
            normal: DVec3::X,
            radius: 1.0,
        };
        let ahead = DiscFrame {
            center: DVec3::new(0.5, 0.0, 0.0),
            normal: DVec3::X,
            radius: 3.0,
        };
        assert!(a.clears(&ahead, 0.01));
        let tilted = DiscFrame {
            center: DVec3::new(0.5, 0.0, 0.0),
            normal: DVec3::new(1.0, 1.0, 0.0).normalize(),
            radius: 1.0,
        };
        assert!(!a.clears(&tilted, 0.01));
        let back = DiscFrame {
            center: DVec3::new(0.5, 0.0, 0.0),
            normal: -DVec3::X,
            radius: 0.1,
        };
        assert!(!a.clears(&back, 0.0));
    }
}
