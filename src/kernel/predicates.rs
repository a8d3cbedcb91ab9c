//! Geometric predicates on triangles, exact where it decides topology.
//!
//! The intersection tests use Shewchuk's adaptive exact orientation predicates
//! (the `robust` crate, which spade also uses), so every sign is the true sign
//! for the given floating-point coordinates: exactly coplanar neighbours (the
//! strips of a straight tube are) are recognised as coplanar, and nearly
//! coplanar ones are decided by their real geometry, not by rounding noise.
//! Touching counts as intersecting (closed triangles). Topological neighbours
//! (pairs sharing a vertex or an edge) have their own tests, since a shared
//! vertex always "touches".

use super::vector::{P3, cross, dot, sub};

fn c3(p: P3) -> robust::Coord3D<f64> {
    robust::Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

fn c2(p: [f64; 2]) -> robust::Coord<f64> {
    robust::Coord { x: p[0], y: p[1] }
}

/// Six times the signed volume of the tetrahedron (a, b, c, d), in plain floating
/// point: positive when d lies on the side of the plane (a, b, c) that its normal
/// (b−a)×(c−a) points to.
#[inline]
pub fn orient3d(a: P3, b: P3, c: P3, d: P3) -> f64 {
    dot(cross(sub(b, a), sub(c, a)), sub(d, a))
}

/// Whether all of `points` lie strictly on one side of the plane of `t`,
/// decided in plain floating point only where that is certain: false when
/// some point is too close to the plane for the rounding error, or the points
/// are on both sides. A filter in front of the exact predicates: most pairs of
/// triangles a mesh compares are plainly apart, and this settles them with one
/// cross product and a few dot products instead of six adaptive determinants.
#[inline]
pub fn certainly_one_side(t: [P3; 3], points: &[P3]) -> bool {
    let (u, v) = (sub(t[1], t[0]), sub(t[2], t[0]));
    let n = cross(u, v);
    let size = |w: P3| w[0].abs().max(w[1].abs()).max(w[2].abs());
    // The rounding error of n·w is below 7ε times the determinant's permanent
    // (Shewchuk's orient3d bound), itself below 6·|u|·|v|·|w| in max norms;
    // 1e-12 is about a hundred times that.
    let scale = 1e-12 * size(u) * size(v);
    let mut side = 0i8;
    for &p in points {
        let w = sub(p, t[0]);
        let d = dot(n, w);
        let margin = scale * size(w);
        let s = if d > margin {
            1
        } else if d < -margin {
            -1
        } else {
            return false;
        };
        if side != 0 && s != side {
            return false;
        }
        side = s;
    }
    side != 0
}

/// The exact sign of [`orient3d`].
#[inline]
pub fn orient3d_sign(a: P3, b: P3, c: P3, d: P3) -> i8 {
    // robust's convention is the opposite: positive when d is below the plane.
    let v = robust::orient3d(c3(a), c3(b), c3(c), c3(d));
    if v < 0.0 {
        1
    } else if v > 0.0 {
        -1
    } else {
        0
    }
}

/// The exact sign of the 2D orientation (positive: counter-clockwise).
#[inline]
pub(crate) fn orient2d_sign(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> i8 {
    let v = robust::orient2d(c2(a), c2(b), c2(c));
    if v > 0.0 {
        1
    } else if v < 0.0 {
        -1
    } else {
        0
    }
}

/// Whether `d` lies strictly inside the circle through the counter-clockwise
/// triangle `a`, `b`, `c` (exact).
#[inline]
pub(crate) fn in_circle(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    robust::incircle(c2(a), c2(b), c2(c), c2(d)) > 0.0
}

/// Whether the closed segment (s, e) meets the closed triangle t.
pub fn segment_hits_triangle(s: P3, e: P3, t: [P3; 3]) -> bool {
    let ds = orient3d_sign(t[0], t[1], t[2], s);
    let de = orient3d_sign(t[0], t[1], t[2], e);
    if ds != 0 && ds == de {
        return false;
    }
    if ds == 0 && de == 0 {
        return coplanar_segment_triangle(s, e, t);
    }
    // The segment crosses (or touches) the plane: the crossing is inside the
    // triangle when the segment's line passes on the same side of all three edges.
    let o1 = orient3d_sign(s, e, t[0], t[1]);
    let o2 = orient3d_sign(s, e, t[1], t[2]);
    let o3 = orient3d_sign(s, e, t[2], t[0]);
    !((o1 > 0 || o2 > 0 || o3 > 0) && (o1 < 0 || o2 < 0 || o3 < 0))
}

/// Drops the axis along which the normal is largest.
fn project2(p: P3, axis: usize) -> [f64; 2] {
    match axis {
        0 => [p[1], p[2]],
        1 => [p[2], p[0]],
        _ => [p[0], p[1]],
    }
}

fn dominant_axis(n: P3) -> usize {
    let a = [n[0].abs(), n[1].abs(), n[2].abs()];
    if a[0] >= a[1] && a[0] >= a[2] {
        0
    } else if a[1] >= a[2] {
        1
    } else {
        2
    }
}

/// Whether the closed 2D segments ab and cd share a point (exact).
pub(crate) fn segments_meet_2d(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    // Segments whose boxes are apart do not meet (exact comparisons): most
    // pairs a polygon's simplicity test looks at.
    for i in 0..2 {
        if a[i].max(b[i]) < c[i].min(d[i]) || c[i].max(d[i]) < a[i].min(b[i]) {
            return false;
        }
    }
    let o1 = orient2d_sign(a, b, c);
    let o2 = orient2d_sign(a, b, d);
    let o3 = orient2d_sign(c, d, a);
    let o4 = orient2d_sign(c, d, b);
    if o1 == 0 && o2 == 0 {
        // Collinear: overlap of the projections on the longer axis.
        let axis = if (b[0] - a[0]).abs() >= (b[1] - a[1]).abs() {
            0
        } else {
            1
        };
        let (lo1, hi1) = (a[axis].min(b[axis]), a[axis].max(b[axis]));
        let (lo2, hi2) = (c[axis].min(d[axis]), c[axis].max(d[axis]));
        return lo1 <= hi2 && lo2 <= hi1;
    }
    o1 * o2 <= 0 && o3 * o4 <= 0
}

/// Whether `p` lies in the closed triangle `t` (exact; either orientation).
pub(crate) fn point_in_triangle_2d(p: [f64; 2], t: [[f64; 2]; 3]) -> bool {
    let o1 = orient2d_sign(t[0], t[1], p);
    let o2 = orient2d_sign(t[1], t[2], p);
    // Strictly on both sides already: outside, whatever the third says.
    if o1 * o2 < 0 {
        return false;
    }
    let o3 = orient2d_sign(t[2], t[0], p);
    !((o1 > 0 || o2 > 0 || o3 > 0) && (o1 < 0 || o2 < 0 || o3 < 0))
}

fn coplanar_segment_triangle(s: P3, e: P3, t: [P3; 3]) -> bool {
    let axis = dominant_axis(cross(sub(t[1], t[0]), sub(t[2], t[0])));
    let t2 = [
        project2(t[0], axis),
        project2(t[1], axis),
        project2(t[2], axis),
    ];
    let (s2, e2) = (project2(s, axis), project2(e, axis));
    point_in_triangle_2d(s2, t2)
        || point_in_triangle_2d(e2, t2)
        || (0..3).any(|i| segments_meet_2d(s2, e2, t2[i], t2[(i + 1) % 3]))
}

/// Whether two closed triangles with no shared vertex intersect.
pub fn triangles_intersect(a: [P3; 3], b: [P3; 3]) -> bool {
    if certainly_one_side(a, &b) || certainly_one_side(b, &a) {
        return false;
    }
    let db: [i8; 3] = std::array::from_fn(|i| orient3d_sign(a[0], a[1], a[2], b[i]));
    if (db[0] > 0 && db[1] > 0 && db[2] > 0) || (db[0] < 0 && db[1] < 0 && db[2] < 0) {
        return false;
    }
    let da: [i8; 3] = std::array::from_fn(|i| orient3d_sign(b[0], b[1], b[2], a[i]));
    if (da[0] > 0 && da[1] > 0 && da[2] > 0) || (da[0] < 0 && da[1] < 0 && da[2] < 0) {
        return false;
    }
    // Any intersection of two triangles is reached by an edge of one of them.
    (0..3).any(|i| segment_hits_triangle(a[i], a[(i + 1) % 3], b))
        || (0..3).any(|i| segment_hits_triangle(b[i], b[(i + 1) % 3], a))
}

/// Whether direction `p` (from `v`) lies strictly inside the wedge spanned by
/// `a1` and `a2` at `v` (all in 2D).
fn strictly_in_wedge(v: [f64; 2], a1: [f64; 2], a2: [f64; 2], p: [f64; 2]) -> bool {
    let turn = orient2d_sign(v, a1, a2);
    turn != 0 && orient2d_sign(v, a1, p) == turn && orient2d_sign(v, p, a2) == turn
}

/// Whether two triangles that share exactly the vertex `a[0] == b[0]` overlap
/// anywhere else.
pub fn triangles_intersect_sharing_vertex(a: [P3; 3], b: [P3; 3]) -> bool {
    if certainly_one_side(a, &[b[1], b[2]]) {
        return false;
    }
    let d1 = orient3d_sign(a[0], a[1], a[2], b[1]);
    let d2 = orient3d_sign(a[0], a[1], a[2], b[2]);
    // All of b but the shared vertex strictly on one side of a's plane: they
    // meet only there. This settles most neighbours in a mesh at once.
    if d1 == d2 && d1 != 0 {
        return false;
    }
    if d1 == 0 && d2 == 0 {
        // Coplanar fans overlap exactly when their wedges at the shared vertex do.
        let axis = dominant_axis(cross(sub(a[1], a[0]), sub(a[2], a[0])));
        let [v, a1, a2] = [
            project2(a[0], axis),
            project2(a[1], axis),
            project2(a[2], axis),
        ];
        let [_, b1, b2] = [
            project2(b[0], axis),
            project2(b[1], axis),
            project2(b[2], axis),
        ];
        let same_ray = |p: [f64; 2], q: [f64; 2]| {
            orient2d_sign(v, p, q) == 0
                && (p[0] - v[0]) * (q[0] - v[0]) + (p[1] - v[1]) * (q[1] - v[1]) > 0.0
        };
        return strictly_in_wedge(v, a1, a2, b1)
            || strictly_in_wedge(v, a1, a2, b2)
            || strictly_in_wedge(v, b1, b2, a1)
            || strictly_in_wedge(v, b1, b2, a2)
            || (same_ray(a1, b1) && same_ray(a2, b2))
            || (same_ray(a1, b2) && same_ray(a2, b1));
    }
    // Otherwise the intersection (a segment from the shared vertex) ends on an
    // opposite edge, which cannot pass through the shared vertex itself.
    segment_hits_triangle(b[1], b[2], a) || segment_hits_triangle(a[1], a[2], b)
}

/// Whether two triangles sharing the edge `(a[0], a[1]) == (b[0], b[1])` in some
/// order fold onto each other (coplanar, third vertices on the same side).
pub fn triangles_fold_on_shared_edge(a: [P3; 3], b: [P3; 3]) -> bool {
    if orient3d_sign(a[0], a[1], a[2], b[2]) != 0 {
        return false;
    }
    let axis = dominant_axis(cross(sub(a[1], a[0]), sub(a[2], a[0])));
    let (p, q) = (project2(a[0], axis), project2(a[1], axis));
    orient2d_sign(p, q, project2(a[2], axis)) == orient2d_sign(p, q, project2(b[2], axis))
}

/// Distance between the segments (a, b) and (c, d).
pub fn segment_distance(a: glam::DVec3, b: glam::DVec3, c: glam::DVec3, d: glam::DVec3) -> f64 {
    let (u, v, w) = (b - a, d - c, a - c);
    let (aa, bb, cc, dd, ee) = (u.dot(u), u.dot(v), v.dot(v), u.dot(w), v.dot(w));
    let den = aa * cc - bb * bb;
    let (mut s, mut t);
    if aa <= 1e-300 && cc <= 1e-300 {
        return a.distance(c);
    }
    if aa <= 1e-300 {
        s = 0.0;
        t = (ee / cc).clamp(0.0, 1.0);
    } else if cc <= 1e-300 {
        t = 0.0;
        s = (-dd / aa).clamp(0.0, 1.0);
    } else {
        s = if den > 1e-12 * aa * cc {
            ((bb * ee - cc * dd) / den).clamp(0.0, 1.0)
        } else {
            0.0
        };
        t = (bb * s + ee) / cc;
        if t < 0.0 {
            t = 0.0;
            s = (-dd / aa).clamp(0.0, 1.0);
        } else if t > 1.0 {
            t = 1.0;
            s = ((bb - dd) / aa).clamp(0.0, 1.0);
        }
    }
    (a + u * s).distance(c + v * t)
}

/// The point of triangle `t` closest to `p` (Ericson, Real-Time Collision
/// Detection, 5.1.5).
pub fn closest_point_on_triangle(p: glam::DVec3, t: [glam::DVec3; 3]) -> glam::DVec3 {
    let [a, b, c] = t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Möller–Trumbore: distance along `dir` (not normalised) to triangle `t`, if the
/// ray from `origin` hits it at a parameter ≥ 0.
pub fn ray_triangle(origin: P3, dir: P3, t: [P3; 3]) -> Option<f64> {
    ray_triangle_near(origin, dir, t).0
}

/// How close to the edge of the test a ray may pass, in barycentric
/// coordinates, before [`ray_triangle_near`] calls it near: far above the
/// rounding of f64 coordinates a cell apart (1e-12 here), far below what a
/// ray in general position comes to.
const RAY_MARGIN: f64 = 1e-7;

/// [`ray_triangle`], and whether the answer is near its edge: the ray passes
/// within 1e-7 (in barycentric coordinates) of the triangle's border (a hit
/// there may be counted by both faces on an edge, or by none), runs nearly in
/// its plane, or meets it next to `origin`. A ray with no near answer on a
/// closed surface counts it exactly.
pub fn ray_triangle_near(origin: P3, dir: P3, t: [P3; 3]) -> (Option<f64>, bool) {
    let e1 = sub(t[1], t[0]);
    let e2 = sub(t[2], t[0]);
    let p = cross(dir, e2);
    let det = dot(e1, p);
    let (edge_sq, dir_len) = (dot(e1, e1).max(dot(e2, e2)), dot(dir, dir).sqrt());
    let scale = edge_sq * dir_len;
    if det.abs() <= 1e-14 * scale {
        return (None, true);
    }
    let flat = det.abs() <= 1e-9 * scale;
    let inv = 1.0 / det;
    let s = sub(origin, t[0]);
    let u = dot(s, p) * inv;
    if !(-RAY_MARGIN..=1.0 + RAY_MARGIN).contains(&u) {
        return (None, flat);
    }
    let q = cross(s, e1);
    let v = dot(dir, q) * inv;
    if v < -RAY_MARGIN || u + v > 1.0 + RAY_MARGIN {
        return (None, flat);
    }
    let t_hit = dot(e2, q) * inv;
    let border =
        u <= RAY_MARGIN || u >= 1.0 - RAY_MARGIN || v <= RAY_MARGIN || u + v >= 1.0 - RAY_MARGIN;
    let size = edge_sq.sqrt() / dir_len;
    let near = flat || border || t_hit.abs() <= RAY_MARGIN * size;
    let inside = (-1e-12..=1.0 + 1e-12).contains(&u) && v >= -1e-12 && u + v <= 1.0 + 1e-12;
    ((inside && t_hit >= 0.0).then_some(t_hit), near)
}

/// Whether faces `fa` and `fb` (vertex indices, positions `ta`, `tb`) intersect,
/// allowing what neighbours legitimately share.
pub fn pair_intersects(fa: [u32; 3], fb: [u32; 3], ta: [[f64; 3]; 3], tb: [[f64; 3]; 3]) -> bool {
    let mut shared = [(0usize, 0usize); 3];
    let mut n = 0;
    for i in 0..3 {
        for j in 0..3 {
            if fa[i] == fb[j] {
                shared[n] = (i, j);
                n += 1;
            }
        }
    }
    match n {
        0 => triangles_intersect(ta, tb),
        1 => {
            let (i, j) = shared[0];
            let a = [ta[i], ta[(i + 1) % 3], ta[(i + 2) % 3]];
            let b = [tb[j], tb[(j + 1) % 3], tb[(j + 2) % 3]];
            triangles_intersect_sharing_vertex(a, b)
        }
        2 => {
            let (i0, j0) = shared[0];
            let (i1, j1) = shared[1];
            let ia = 3 - i0 - i1;
            let ib = 3 - j0 - j1;
            triangles_fold_on_shared_edge([ta[i0], ta[i1], ta[ia]], [tb[j0], tb[j1], tb[ib]])
        }
        _ => false, // duplicate faces are reported separately
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: [P3; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

    #[test]
    fn the_filter_only_answers_what_the_exact_signs_say() {
        // Points on, near and off the planes of random thin and fat triangles.
        let mut h = 7u64;
        let mut unit = || {
            h = crate::kernel::hash::mix64(h);
            (h >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut decided = 0;
        for k in 0..20_000 {
            let scale = [1e-3, 1.0, 1e4][k % 3];
            let t: [P3; 3] = std::array::from_fn(|_| std::array::from_fn(|_| scale * unit()));
            let p: [P3; 3] = std::array::from_fn(|i| {
                // Every fourth point in the plane (up to rounding).
                let (a, b) = (unit().abs(), unit().abs());
                if (k + i) % 4 == 0 {
                    std::array::from_fn(|c| {
                        t[0][c] + a * (t[1][c] - t[0][c]) + b * (t[2][c] - t[0][c])
                    })
                } else {
                    std::array::from_fn(|_| scale * unit())
                }
            });
            let exact: Vec<i8> = p
                .iter()
                .map(|&q| orient3d_sign(t[0], t[1], t[2], q))
                .collect();
            if certainly_one_side(t, &p) {
                decided += 1;
                assert!(
                    exact[0] != 0 && exact.iter().all(|&s| s == exact[0]),
                    "{t:?} {p:?}"
                );
            }
        }
        assert!(decided > 1000, "{decided}");
    }

    #[test]
    fn crossing_and_separate_triangles() {
        let piercing = [[0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.3, 0.5, 0.5]];
        assert!(triangles_intersect(T, piercing));
        let above = [[0.2, 0.2, 0.1], [0.2, 0.5, 1.0], [0.6, 0.2, 1.0]];
        assert!(!triangles_intersect(T, above));
        let beside = [[2.0, 0.0, -1.0], [2.0, 0.0, 1.0], [2.0, 1.0, 0.0]];
        assert!(!triangles_intersect(T, beside));
    }

    #[test]
    fn coplanar_overlap_and_disjoint() {
        let overlap = [[0.2, 0.2, 0.0], [1.2, 0.2, 0.0], [0.2, 1.2, 0.0]];
        assert!(triangles_intersect(T, overlap));
        let apart = [[2.0, 2.0, 0.0], [3.0, 2.0, 0.0], [2.0, 3.0, 0.0]];
        assert!(!triangles_intersect(T, apart));
    }

    #[test]
    fn shared_vertex_cases() {
        // A proper fan neighbour: no overlap.
        let fan = [[0.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]];
        assert!(!triangles_intersect_sharing_vertex(T, fan));
        // Non-coplanar neighbour whose far edge pierces T.
        let pierce = [[0.0, 0.0, 0.0], [0.3, 0.3, -1.0], [0.3, 0.3, 1.0]];
        assert!(triangles_intersect_sharing_vertex(T, pierce));
        // Coplanar, one sector inside the other.
        let inside = [[0.0, 0.0, 0.0], [0.5, 0.1, 0.0], [0.1, 0.5, 0.0]];
        assert!(triangles_intersect_sharing_vertex(T, inside));
    }

    #[test]
    fn coplanar_neighbours_in_a_strip_do_not_intersect() {
        // Two triangles of a straight tube's strip, exactly coplanar, sharing one
        // vertex; f32-like coordinates far from the origin.
        let a = [
            [428.41558837890625, -378.8808059692383, 90.04707007855177],
            [428.34503173828125, -378.8163528442383, 90.04707007855177],
            [428.40911865234375, -378.8878860473633, 90.10665564984083],
        ];
        let b = [
            [428.41558837890625, -378.8808059692383, 90.04707007855177],
            [428.47967529296875, -378.9523391723633, 90.10665564984083],
            [428.48614501953125, -378.9452590942383, 90.04707007855177],
        ];
        assert!(!triangles_intersect_sharing_vertex(a, b));
    }

    #[test]
    fn folded_shared_edge() {
        let folded = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.5, 0.0]];
        assert!(triangles_fold_on_shared_edge(T, folded));
        let proper = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, -0.5, 0.0]];
        assert!(!triangles_fold_on_shared_edge(T, proper));
        let bent = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.5, 0.5]];
        assert!(!triangles_fold_on_shared_edge(T, bent));
    }

    #[test]
    fn closest_points() {
        use glam::DVec3;
        let t = [DVec3::ZERO, DVec3::X, DVec3::Y];
        let near = |p: DVec3, want: DVec3| {
            let got = closest_point_on_triangle(p, t);
            assert!((got - want).length() < 1e-12, "{p} gives {got}, not {want}");
        };
        near(DVec3::new(0.2, 0.2, 5.0), DVec3::new(0.2, 0.2, 0.0));
        near(DVec3::new(-1.0, -1.0, 0.0), DVec3::ZERO);
        near(DVec3::new(0.5, -2.0, 1.0), DVec3::new(0.5, 0.0, 0.0));
        near(DVec3::new(1.0, 1.0, 0.0), DVec3::new(0.5, 0.5, 0.0));
    }

    #[test]
    fn ray_hits() {
        let t = ray_triangle([0.2, 0.2, 1.0], [0.0, 0.0, -2.0], T).unwrap();
        assert!((t - 0.5).abs() < 1e-12);
        assert!(ray_triangle([0.2, 0.2, 1.0], [0.0, 0.0, 1.0], T).is_none());
        assert!(ray_triangle([2.0, 2.0, 1.0], [0.0, 0.0, -1.0], T).is_none());
    }

    #[test]
    fn rays_near_a_border_are_told() {
        let down = [0.0, 0.0, -1.0];
        // Well inside, well outside: exact answers.
        assert_eq!(
            ray_triangle_near([0.2, 0.3, 1.0], down, T),
            (Some(1.0), false)
        );
        assert_eq!(ray_triangle_near([0.9, 0.9, 1.0], down, T), (None, false));
        // On an edge, a corner, just outside an edge: near, whatever the hit.
        assert!(ray_triangle_near([0.5, 0.0, 1.0], down, T).1);
        assert!(ray_triangle_near([0.0, 0.0, 1.0], down, T).1);
        assert!(ray_triangle_near([0.5, 0.5 + 1e-9, 1.0], down, T).1);
        // In the plane, and from a point on the triangle.
        assert!(ray_triangle_near([0.2, 0.2, 0.0], [1.0, 0.0, 0.0], T).1);
        assert!(ray_triangle_near([0.2, 0.2, 0.0], [0.0, 0.0, 1.0], T).1);
    }
}
