//! Where a line meets a round cone: an exact interval.

use glam::DVec3;

use crate::kernel::round_cone::RoundCone;

/// The interval of parameters `t` for which `o + t·dir` (`dir` of unit
/// length) lies in the round cone, or `None` if the line misses it.
///
/// A round cone is the union of its end spheres and the frustum between the
/// circles where the tangent cone touches them; all three are convex and so
/// is their union, so its interval is the hull of theirs.
pub(crate) fn line_interval(c: &RoundCone, o: DVec3, dir: DVec3) -> Option<(f64, f64)> {
    let mut hull = sphere_interval(c.a, c.ra, o, dir);
    if c.a == c.b {
        return hull;
    }
    let mut join = |s: Option<(f64, f64)>| {
        if let Some((lo, hi)) = s {
            hull = Some(hull.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
        }
    };
    join(sphere_interval(c.b, c.rb, o, dir));
    join(frustum_interval(c, o, dir));
    hull
}

fn sphere_interval(center: DVec3, r: f64, o: DVec3, dir: DVec3) -> Option<(f64, f64)> {
    let w = o - center;
    let b = w.dot(dir);
    let disc = b * b - (w.length_squared() - r * r);
    (disc >= 0.0).then(|| {
        let s = disc.sqrt();
        (-b - s, -b + s)
    })
}

/// The interval of the frustum between the tangent circles: the axial
/// coordinate `x` between theirs and the distance from the axis at most the
/// radius `ρ(x)`, linear between the circles' radii.
fn frustum_interval(c: &RoundCone, o: DVec3, dir: DVec3) -> Option<(f64, f64)> {
    let ab = c.b - c.a;
    let d = ab.length();
    let u = ab / d;
    let sin = (c.ra - c.rb) / d;
    if sin.abs() >= 1.0 {
        return None;
    }
    let cos = (1.0 - sin * sin).sqrt();
    let (xa, xb) = (c.ra * sin, d + c.rb * sin);
    let (pa, pb) = (c.ra * cos, c.rb * cos);
    let k = (pb - pa) / (xb - xa);
    let w = o - c.a;
    let (x0, vx) = (w.dot(u), dir.dot(u));
    let (w0, w1) = (w - u * x0, dir - u * vx);
    // Within the slab xa ≤ x ≤ xb, which holds the frustum.
    let (lo, hi) = if vx.abs() > 1e-12 {
        let (t0, t1) = ((xa - x0) / vx, (xb - x0) / vx);
        (t0.min(t1), t0.max(t1))
    } else if (xa..=xb).contains(&x0) {
        // Parallel to the axis: the radial test alone decides, and it is
        // one quadratic with a positive leading term; bound t by the cone's
        // own size so the candidates below stay finite.
        let r = c.ra.max(c.rb) + d + w.length();
        (-r, r)
    } else {
        return None;
    };
    // q(t) = |radial|² − ρ(x(t))², at most zero inside.
    let rho0 = pa + k * (x0 - xa);
    let qa = w1.length_squared() - k * k * vx * vx;
    let qb = 2.0 * (w0.dot(w1) - k * vx * rho0);
    let qc = w0.length_squared() - rho0 * rho0;
    let q = |t: f64| (qa * t + qb) * t + qc;
    // The frustum is convex, so the line's part of it is one interval whose
    // ends are among the slab's ends and q's roots between them: test the
    // middle of each piece between consecutive candidates.
    let mut cuts = [lo, hi, lo, lo];
    let mut count = 2;
    for root in roots(qa, qb, qc) {
        if root > lo && root < hi {
            cuts[count] = root;
            count += 1;
        }
    }
    let cuts = &mut cuts[..count];
    cuts.sort_unstable_by(f64::total_cmp);
    let mut hull: Option<(f64, f64)> = None;
    for pair in cuts.windows(2) {
        if pair[1] > pair[0] && q(0.5 * (pair[0] + pair[1])) <= 0.0 {
            hull = Some(hull.map_or((pair[0], pair[1]), |(a, _)| (a, pair[1])));
        }
    }
    hull
}

/// The real roots of `a·t² + b·t + c` (none, one or two), computed without
/// cancellation.
fn roots(a: f64, b: f64, c: f64) -> impl Iterator<Item = f64> {
    let mut out = [f64::NAN; 2];
    let scale = a.abs().max(b.abs()).max(c.abs());
    if scale > 0.0 && a.abs() > 1e-14 * scale {
        let disc = b * b - 4.0 * a * c;
        if disc >= 0.0 {
            let q = -0.5 * (b + b.signum() * disc.sqrt());
            out[0] = q / a;
            out[1] = if q != 0.0 { c / q } else { q / a };
        }
    } else if b != 0.0 {
        out[0] = -c / b;
    }
    out.into_iter().filter(|t| t.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::rng::Rng;

    /// The interval agrees with the cone's own inside test along many
    /// random lines, through and near a tapered cone.
    #[test]
    fn intervals_match_the_inside_test() {
        let tapered = RoundCone {
            a: DVec3::new(0.3, -0.2, 0.1),
            ra: 2.0,
            b: DVec3::new(5.0, 1.0, -0.5),
            rb: 0.6,
        };
        let cylinder = RoundCone {
            a: DVec3::new(4.0, 0.0, 0.0),
            ra: 1.0,
            b: DVec3::new(10.0, 0.0, 0.0),
            rb: 1.0,
        };
        for c in [tapered, cylinder] {
            along_random_lines(&c);
        }
    }

    fn along_random_lines(c: &RoundCone) {
        let mut rng = Rng::new(11);
        let mut met = 0;
        for _ in 0..2000 {
            let mut at = || DVec3::new(rng.f64(), rng.f64(), rng.f64()) * 10.0 - 3.0;
            let (o, to) = (at(), at());
            let dir = (to - o).normalize();
            let span = line_interval(c, o, dir);
            for k in 0..400 {
                let t = -20.0 + 0.1 * f64::from(k) + 0.0137;
                let inside = c.sdf(o + dir * t) < -1e-9;
                let outside = c.sdf(o + dir * t) > 1e-9;
                let within = span.is_some_and(|(lo, hi)| lo <= t && t <= hi);
                assert!(!inside || within, "t {t} inside but not in {span:?}");
                assert!(!outside || !within, "t {t} outside but in {span:?}");
            }
            met += usize::from(span.is_some());
        }
        assert!(met > 100, "only {met} lines met the cone");
    }
}
