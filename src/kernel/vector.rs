//! Vectors: one vocabulary per job.
//!
//! Construction (splines, frames, contours, tubes) computes with glam's
//! `DVec3`. Meshes store plain arrays, `[f32; 3]` ([`V3`]) on output and
//! `[f64; 3]` ([`P3`]) where the exact predicates of
//! [`super::predicates`] read them (the `robust` crate takes coordinates,
//! not vectors); the helpers below are the array side's arithmetic.

use glam::DVec3;

/// A point or vector.
pub type P3 = [f64; 3];

/// A vertex as the output holds it. The overlap pass keeps its vertices so,
/// the new ones rounded at once, and reads them in f64 through [`at`]
/// rather than holding an f64 copy of them all.
pub type V3 = [f32; 3];

/// Vertex `k` of `pos`, in f64 (exactly).
#[inline]
pub fn at(pos: &[V3], k: u32) -> P3 {
    pos[k as usize].map(f64::from)
}

/// `a − b`.
#[inline]
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
/// `a × b`.
#[inline]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// `a · b`.
#[inline]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// `|a|`.
#[inline]
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// The lowest and highest corner of the box around `points` (zero when
/// there are none).
pub fn bounds(points: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    if points.is_empty() {
        return ([0.0; 3], [0.0; 3]);
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
}

/// A unit vector perpendicular to `o`, chosen deterministically.
pub fn any_perpendicular(o: DVec3) -> DVec3 {
    let a = o.abs();
    let e = if a.x <= a.y && a.x <= a.z {
        DVec3::X
    } else if a.y <= a.z {
        DVec3::Y
    } else {
        DVec3::Z
    };
    (e - e.dot(o) * o).normalize()
}
