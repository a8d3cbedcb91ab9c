//! Tip caps: a free end closed by a dome inside the end sample's sphere,
//! `cap_rings` rings at heights r·sin φ and radii r·cos φ (φ evenly spaced in
//! (0, π/2)) and an apex at distance r: a polygonal hemisphere, the round
//! cone's end cap. With `cap_rings = 0` the end is a flat fan. A capsule is a
//! straight tube capped at both ends.

use glam::DVec3;

use super::Ring;
use super::band::connect;
use crate::build::surface::Surface;
use crate::skeleton::contour;

/// A closed capsule from `a` to `b` of (nominal) radius `radius`: parallel
/// rings of `m` vertices about the straight axis, about one edge length
/// apart, and a dome at each end. Convex, so it cannot cross itself; used to
/// join two parts by their union where no splice was valid.
pub fn capsule(
    surface: &mut Surface,
    a: DVec3,
    b: DVec3,
    radius: f64,
    m: u32,
    label: u32,
    cap_rings: u32,
) {
    let axis = b - a;
    let length = axis.length();
    let normal = if length > 0.0 {
        axis / length
    } else {
        DVec3::Z
    };
    let u = crate::kernel::vector::any_perpendicular(normal);
    let r = contour::polygon_radius(radius, m);
    let edge = std::f64::consts::TAU * r / f64::from(m);
    let steps = ((length / edge).ceil() as u32).clamp(1, 256);
    let rings: Vec<Ring> = (0..=steps)
        .map(|k| {
            let center = a + axis * (f64::from(k) / f64::from(steps));
            let first = surface.pos.len() as u32;
            for p in contour::ring(center, normal, u, r, m) {
                surface.vertex(p, label);
            }
            Ring {
                center,
                normal,
                u,
                radius: r,
                skeleton_radius: radius,
                m,
                first,
                label,
                source: 0,
                resampled: 0,
            }
        })
        .collect();
    for w in rings.windows(2) {
        connect(surface, &w[0], &w[1]);
    }
    cap(surface, &rings[0], cap_rings, false);
    cap(surface, &rings[steps as usize], cap_rings, true);
}

/// Closes the tube after `ring` (if `forward`) or before it with a dome of
/// `rings` rings and an apex, inside the sphere of the ring's radius.
/// Returns the triangle range and the range of vertices it added.
pub fn cap(
    surface: &mut Surface,
    ring: &Ring,
    rings: u32,
    forward: bool,
) -> (std::ops::Range<u32>, std::ops::Range<u32>) {
    let t0 = surface.tris.len() as u32;
    let v0 = surface.pos.len() as u32;
    let dir = if forward { ring.normal } else { -ring.normal };
    // The dome's meridian is a polygon of 4·(rings + 1) sides inscribed in a
    // quarter circle; enlarge it like the contours (see `polygon_radius`) so the
    // cap's area and volume errors stay balanced too.
    let r = contour::polygon_radius(ring.radius, 4 * (rings + 1));
    let mut prev = *ring;
    for k in 1..=rings {
        let phi = std::f64::consts::FRAC_PI_2 * f64::from(k) / f64::from(rings + 1);
        let center = ring.center + dir * (r * phi.sin());
        let first = surface.pos.len() as u32;
        for p in contour::ring(center, ring.normal, ring.u, r * phi.cos(), ring.m) {
            surface.vertex(p, ring.label);
        }
        let next = Ring {
            center,
            first,
            ..*ring
        };
        if forward {
            connect(surface, &prev, &next);
        } else {
            connect(surface, &next, &prev);
        }
        prev = next;
    }
    let apex = surface.vertex(ring.center + dir * r, ring.label);
    for j in 0..prev.m {
        let (a, b) = (prev.vertex(j), prev.vertex(j + 1));
        if forward {
            surface.triangle(a, b, apex);
        } else {
            surface.triangle(b, a, apex);
        }
    }
    (t0..surface.tris.len() as u32, v0..surface.pos.len() as u32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::tube::place_ring;
    use crate::build::tube::tests::straight;
    use crate::mesh::BuildStats;

    #[test]
    fn capped_segment_is_a_closed_outward_capsule() {
        for rings in [0, 3] {
            let track = straight(2, 1.0);
            let mut s = Surface::default();
            let a = place_ring(&mut s, &track, 0, track.frames[0], &[0, 1]);
            let b = place_ring(
                &mut s,
                &track,
                track.samples.len() - 1,
                track.frames[0],
                &[0, 1],
            );
            connect(&mut s, &a, &b);
            cap(&mut s, &a, rings, false);
            cap(&mut s, &b, rings, true);
            let mesh = s.into_mesh(BuildStats::default());
            let r = mesh.check();
            assert!(r.is_valid(), "{rings} rings: {r}");
            assert_eq!(r.euler_characteristic, 2);
            if rings == 3 {
                // Cylinder of length 2 and radius 1 plus a sphere of radius 1.
                let exact = std::f64::consts::PI * 2.0 + 4.0 / 3.0 * std::f64::consts::PI;
                assert!(
                    (mesh.volume() / exact - 1.0).abs() < 0.02,
                    "{}",
                    mesh.volume()
                );
            }
        }
    }
}
