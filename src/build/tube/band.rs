//! Contour connection (paper §3.2): the band of triangles between two
//! contours.
//!
//! Starting from the two first vertices (which correspond, thanks to the
//! push-forward frames), each step adds one triangle, advancing on whichever
//! contour comes next in angle about the axis P_iP_{i+1}: the paper's minimum
//! included-angle rule, in a form that provably never folds a band (see
//! [`connect_loops`]). The result has m_i + m_{i+1} triangles, (a_i, a_{i+1},
//! b_j) and (a_i, b_{j+1}, b_j), which face outward for contours running
//! counter-clockwise about the direction of travel.

use glam::DVec3;

use super::Ring;
use crate::build::surface::Surface;

/// Connects ring `a` (behind) to ring `b` (in front).
pub fn connect(surface: &mut Surface, a: &Ring, b: &Ring) {
    connect_loops(surface, &ring_loop(a), &ring_loop(b), a.center, b.center);
}

/// The vertex indices of a ring in order.
pub fn ring_loop(r: &Ring) -> Vec<u32> {
    (0..r.m).map(|j| r.first + j).collect()
}

/// Connects two vertex loops that both wind once, counter-clockwise, about the
/// axis from `ca` (centre of `a`, behind) to `cb` (centre of `b`, in front).
///
/// This is the paper's contour connection with its criterion made robust. The
/// paper projects C_i onto a plane parallel to C_{i+1}, starts from the first
/// vertices and adds, step by step, the triangle whose new diagonal makes the
/// smaller angle with P_iP_{i+1}. We project both loops along the axis P_iP_{i+1}
/// itself and take the vertex that comes next in angle about the axis. For
/// similar parallel contours the two rules pick the same triangles; at sharp
/// turns (strongly tilted contours close together) the literal rule can let
/// diagonals cross and fold the band, while the angular order cannot: along any
/// segment that misses the axis the angle about it is monotonic, so each triangle
/// occupies its own angular sector, and only triangles that share an edge meet.
/// The start is `a`'s first vertex and the vertex of `b` nearest to it in angle
/// (the corresponding first vertex, for push-forward contours).
pub fn connect_loops(surface: &mut Surface, a: &[u32], b: &[u32], ca: DVec3, cb: DVec3) {
    let d = (cb - ca).normalize_or_zero();
    let d = if d == DVec3::ZERO { DVec3::Z } else { d };
    connect_loops_about(surface, a, b, ca, cb, d);
}

/// [`connect_loops`] with the axis direction given: angles of `a` are measured
/// about the line through `ca`, those of `b` about the parallel line through
/// `cb`. Used where the two loops share a centre (a region's rim and a contour
/// lying over it).
pub fn connect_loops_about(
    surface: &mut Surface,
    a: &[u32],
    b: &[u32],
    ca: DVec3,
    cb: DVec3,
    d: DVec3,
) {
    let e1 = crate::kernel::vector::any_perpendicular(d);
    let e2 = d.cross(e1);
    if !connect_by_pseudo_angles(surface, a, b, ca, cb, e1, e2) {
        connect_by_angles(surface, a, b, ca, cb, e1, e2);
    }
}

/// The general path of [`connect_loops_about`]: angles by `atan2`, and a
/// loop that does not wind monotonically parameterised by its length.
fn connect_by_angles(
    surface: &mut Surface,
    a: &[u32],
    b: &[u32],
    ca: DVec3,
    cb: DVec3,
    e1: DVec3,
    e2: DVec3,
) {
    let tau = std::f64::consts::TAU;
    let pi = std::f64::consts::PI;
    let angle_of = |k: u32, c: DVec3| {
        let p = surface.pos[k as usize] - c;
        p.dot(e2).atan2(p.dot(e1))
    };
    let a_raw: Vec<f64> = a.iter().map(|&k| angle_of(k, ca)).collect();
    let b_raw: Vec<f64> = b.iter().map(|&k| angle_of(k, cb)).collect();
    // Start of b: the vertex nearest in angle to a's first vertex.
    let near = |t: f64| (t - a_raw[0] + pi).rem_euclid(tau) - pi;
    let start_b = (0..b.len())
        .min_by(|&x, &y| near(b_raw[x]).abs().total_cmp(&near(b_raw[y]).abs()))
        .unwrap_or(0);
    let b: Vec<u32> = (0..b.len()).map(|k| b[(start_b + k) % b.len()]).collect();
    let b_raw: Vec<f64> = (0..b.len())
        .map(|k| b_raw[(start_b + k) % b.len()])
        .collect();
    let ta = loop_parameter(surface, a, &a_raw, a_raw[0]);
    let tb = loop_parameter(surface, &b, &b_raw, a_raw[0] + near(b_raw[0]));
    merge_loops(surface, a, &ta, &b, 0, &tb, tau);
}

/// A strictly increasing function of the angle of `(x, y)` over one turn,
/// in [0, 4) (the "diamond angle"): what [`connect_loops_about`] needs of an
/// angle is its order, and this gives the same order as `atan2` without its
/// cost (`atan2` was 4.3 % of a whole cell's profile, Allen 177300).
fn pseudo_angle(x: f64, y: f64) -> f64 {
    if y >= 0.0 {
        if x >= 0.0 {
            y / (x + y)
        } else {
            1.0 - x / (y - x)
        }
    } else if x < 0.0 {
        2.0 - y / (-x - y)
    } else {
        3.0 + x / (x - y)
    }
}

/// [`connect_loops_about`] for the common case, two loops whose vertices
/// wind strictly monotonically about the axis, with angles replaced by
/// [`pseudo_angle`] (period 4). As every step only compares angles, the band
/// is the one the angles give. Returns `false`, having added nothing, when a
/// loop does not wind monotonically or a vertex lies on the axis; the caller
/// then takes the general path.
fn connect_by_pseudo_angles(
    surface: &mut Surface,
    a: &[u32],
    b: &[u32],
    ca: DVec3,
    cb: DVec3,
    e1: DVec3,
    e2: DVec3,
) -> bool {
    const TURN: f64 = 4.0;
    let (ma, mb) = (a.len(), b.len());
    if ma == 0 || mb == 0 {
        return false;
    }
    let pos = &surface.pos;
    let plane = |k: u32, c: DVec3| {
        let p = pos[k as usize] - c;
        (p.dot(e1), p.dot(e2))
    };
    let (xa, ya) = plane(a[0], ca);
    if xa == 0.0 && ya == 0.0 {
        return false;
    }
    let mut t: Vec<f64> = Vec::with_capacity(ma + mb);
    let a0 = pseudo_angle(xa, ya);
    t.push(a0);
    for &k in &a[1..] {
        let (x, y) = plane(k, ca);
        let u = a0 + within_turn(pseudo_angle(x, y) - a0, TURN);
        if u <= t[t.len() - 1] {
            return false;
        }
        t.push(u);
    }
    // b starts at its vertex nearest in angle to a's first (largest cosine;
    // the first of equals, as the general path takes).
    let mut start_b = 0;
    let mut best = f64::NEG_INFINITY;
    for (j, &k) in b.iter().enumerate() {
        let (x, y) = plane(k, cb);
        let n = (x * x + y * y).sqrt();
        if n == 0.0 {
            return false;
        }
        let c = (x * xa + y * ya) / n;
        if c > best {
            best = c;
            start_b = j;
        }
    }
    // Its parameter is a's start plus their difference taken within half a
    // turn: b's start is the nearest, at most a quarter turn away, so the side
    // cannot be mistaken (a sign test of the two directions could be, by a
    // rounding, and put all of b a turn behind).
    let (xb, yb) = plane(b[start_b], cb);
    let half = TURN / 2.0;
    let mut prev = a0 + ((pseudo_angle(xb, yb) - a0 + half).rem_euclid(TURN) - half);
    t.push(prev);
    for k in 1..mb {
        let (x, y) = plane(b[wrapped(start_b + k, mb)], cb);
        // Unwrapped from b's start, as the general path does.
        let u = t[ma] + within_turn(pseudo_angle(x, y) - t[ma], TURN);
        if u <= prev {
            return false;
        }
        t.push(u);
        prev = u;
    }
    let (ta, tb) = t.split_at(ma);
    merge_loops(surface, a, ta, b, start_b, tb, TURN);
    true
}

/// `k % m` for `k < 2 m`, by a comparison: a division per index was a
/// visible share of a band's cost, which is a triangle per step.
#[inline]
fn wrapped(k: usize, m: usize) -> usize {
    if k >= m { k - m } else { k }
}

/// `x.rem_euclid(turn)`, bit for bit, without the division where `x` is
/// less than a turn from 0 (two pseudo-angles apart: nearly always). Per
/// vertex of every band, `fmod` was a visible share of the connection.
#[inline]
fn within_turn(x: f64, turn: f64) -> f64 {
    if (0.0..turn).contains(&x) {
        x
    } else if x < 0.0 && x > -turn {
        x + turn
    } else {
        x.rem_euclid(turn)
    }
}

/// Parameters for a loop's vertices, increasing from `start` over one turn:
/// their angles when those increase monotonically (always, for a contour),
/// otherwise the fraction of the loop's length (a region's jagged rim).
fn loop_parameter(surface: &Surface, lp: &[u32], raw: &[f64], start: f64) -> Vec<f64> {
    let tau = std::f64::consts::TAU;
    // The first vertex is at `start` (which differs from its angle only by
    // turns and rounding): unwrapped, a rounding below it would put it a
    // whole turn ahead and throw the loop onto the length rule.
    let unwrapped: Vec<f64> = std::iter::once(start)
        .chain(
            raw[1..]
                .iter()
                .map(|&t| start + (t - start).rem_euclid(tau)),
        )
        .collect();
    if unwrapped.windows(2).all(|w| w[1] > w[0]) {
        return unwrapped;
    }
    let n = lp.len();
    let step =
        |i: usize| surface.pos[lp[i] as usize].distance(surface.pos[lp[(i + 1) % n] as usize]);
    let total: f64 = (0..n).map(step).sum::<f64>().max(1e-300);
    let mut acc = 0.0;
    (0..n)
        .map(|i| {
            let t = start + tau * acc / total;
            acc += step(i);
            t
        })
        .collect()
}

/// Joins two loops whose vertices carry increasing parameters over one turn
/// of length `turn` (`ta[0]` and `tb[0]` the corresponding starts; `b` read
/// from its vertex `b_start` on): each step advances on the loop whose next
/// vertex comes first, so the m + n triangles form a band.
fn merge_loops(
    surface: &mut Surface,
    a: &[u32],
    ta: &[f64],
    b: &[u32],
    b_start: usize,
    tb: &[f64],
    turn: f64,
) {
    let (ma, mb) = (a.len(), b.len());
    let b_start = b_start % mb.max(1);
    // Vertex k (0 ≤ k ≤ mb) of `b` read from `b_start`.
    let b_at = |k: usize| b[wrapped(b_start + wrapped(k, mb), mb)];
    let next = |t: &[f64], k: usize| if k < t.len() { t[k] } else { t[0] + turn };
    let (mut i, mut j) = (0usize, 0usize);
    while i < ma || j < mb {
        let advance_b = if i == ma {
            true
        } else if j == mb {
            false
        } else {
            next(tb, j + 1) < next(ta, i + 1)
        };
        if advance_b {
            surface.triangle(a[wrapped(i, ma)], b_at(j + 1), b_at(j));
            j += 1;
        } else {
            surface.triangle(a[wrapped(i, ma)], a[wrapped(i + 1, ma)], b_at(j));
            i += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skeleton::contour;

    #[test]
    fn within_turn_is_rem_euclid_bit_for_bit() {
        let mut rng = crate::kernel::rng::Rng::new(0x9e37_79b9_7f4a_7c15);
        let tiny = f64::from_bits(1);
        let mut xs = vec![
            0.0,
            -0.0,
            4.0,
            -4.0,
            tiny,
            -tiny,
            4.0 - 1e-15,
            -4.0 + 1e-15,
            -1e-17,
            8.0,
            -8.5,
            1e300,
            f64::NAN,
            f64::INFINITY,
        ];
        xs.extend((0..10_000).map(|_| 24.0 * rng.f64() - 12.0));
        for x in xs {
            let (got, want) = (within_turn(x, 4.0), x.rem_euclid(4.0));
            assert!(
                got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                "{x}: {got} against {want}"
            );
        }
    }

    /// The pseudo-angle path builds the band the angle path builds, on
    /// random pairs of tilted, shifted contours of different sizes.
    #[test]
    fn pseudo_angles_give_the_band_angles_give() {
        let mut rng = crate::kernel::rng::Rng::new(0x2545_f491_4f6c_dd1d);
        let mut rnd = move || rng.f64();
        let loop_at = |s: &mut Surface, c: DVec3, n: DVec3, m: u32, r: f64, turn: f64| {
            let u = crate::kernel::vector::any_perpendicular(n);
            let u = u * turn.cos() + n.cross(u) * turn.sin();
            let first = s.pos.len() as u32;
            for p in contour::ring(c, n, u, r, m) {
                s.vertex(p, 0);
            }
            (first..first + m).collect::<Vec<u32>>()
        };
        let mut fast_taken = 0;
        for _ in 0..3000 {
            let mut s = Surface::with_capacity(256);
            let ca = DVec3::ZERO;
            let cb = DVec3::new(0.3 * (rnd() - 0.5), 0.3 * (rnd() - 0.5), 0.05 + rnd());
            let na = DVec3::new(1.5 * (rnd() - 0.5), 1.5 * (rnd() - 0.5), 1.0).normalize();
            let nb = DVec3::new(1.5 * (rnd() - 0.5), 1.5 * (rnd() - 0.5), 1.0).normalize();
            let ma = 4 + 2 * (rnd() * 20.0) as u32;
            let mb = 4 + 2 * (rnd() * 20.0) as u32;
            let (ra, rb, turn_a, turn_b) = (0.5 + rnd(), 0.5 + rnd(), rnd() * 6.3, rnd() * 6.3);
            let a = loop_at(&mut s, ca, na, ma, ra, turn_a);
            let b = loop_at(&mut s, cb, nb, mb, rb, turn_b);
            let d = (cb - ca).normalize();
            let e1 = crate::kernel::vector::any_perpendicular(d);
            let e2 = d.cross(e1);
            let mut fast = s.clone();
            let mut slow = s;
            if connect_by_pseudo_angles(&mut fast, &a, &b, ca, cb, e1, e2) {
                fast_taken += 1;
                connect_by_angles(&mut slow, &a, &b, ca, cb, e1, e2);
                assert_eq!(fast.tris, slow.tris);
            } else {
                assert!(fast.tris.is_empty());
            }
        }
        assert!(fast_taken > 1000, "{fast_taken}");
    }
}
