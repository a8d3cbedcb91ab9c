//! Small exact-in-spirit geometric predicates on f64 triangles.
//!
//! The intersection tests are built on one orientation determinant, so the same
//! sign convention decides every case, and touching counts as intersecting
//! (closed triangles): a vertex lying exactly on another triangle is a defect for
//! a mesh that must be free of self-intersections. Topological neighbours (pairs
//! that share a vertex or an edge) have their own tests, because a shared vertex
//! always "intersects".

use crate::mesh::{cross, dot, sub};

/// A point or vector.
pub type P3 = [f64; 3];

/// Six times the signed volume of the tetrahedron (a, b, c, d): positive when d
/// lies on the side of the plane (a, b, c) that its normal (b-a)×(c-a) points to.
#[inline]
pub fn orient3d(a: P3, b: P3, c: P3, d: P3) -> f64 {
    dot(cross(sub(b, a), sub(c, a)), sub(d, a))
}

/// Sign with a zero band relative to the magnitudes involved.
#[inline]
fn sign(v: f64, scale: f64) -> i8 {
    let eps = 1e-13 * scale;
    if v > eps {
        1
    } else if v < -eps {
        -1
    } else {
        0
    }
}

fn scale_of(points: &[P3]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    let d = (0..3).map(|a| hi[a] - lo[a]).fold(0.0, f64::max);
    d * d * d
}

/// Whether the closed segment (s, e) meets the closed triangle t.
pub fn segment_hits_triangle(s: P3, e: P3, t: [P3; 3]) -> bool {
    let scale = scale_of(&[s, e, t[0], t[1], t[2]]);
    let ds = sign(orient3d(t[0], t[1], t[2], s), scale);
    let de = sign(orient3d(t[0], t[1], t[2], e), scale);
    if ds != 0 && ds == de {
        return false;
    }
    if ds == 0 && de == 0 {
        return coplanar_segment_triangle(s, e, t);
    }
    // The segment crosses the plane: the crossing is inside the triangle when the
    // segment's line passes on the same side of all three edges.
    let o1 = sign(orient3d(s, e, t[0], t[1]), scale);
    let o2 = sign(orient3d(s, e, t[1], t[2]), scale);
    let o3 = sign(orient3d(s, e, t[2], t[0]), scale);
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

fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

fn segments_cross_2d(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2], scale: f64) -> bool {
    let o1 = sign(orient2d(a, b, c), scale);
    let o2 = sign(orient2d(a, b, d), scale);
    let o3 = sign(orient2d(c, d, a), scale);
    let o4 = sign(orient2d(c, d, b), scale);
    if o1 != o2 && o3 != o4 && !(o1 == 0 && o2 == 0) {
        return true;
    }
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
    false
}

fn point_in_triangle_2d(p: [f64; 2], t: [[f64; 2]; 3], scale: f64) -> bool {
    let o1 = sign(orient2d(t[0], t[1], p), scale);
    let o2 = sign(orient2d(t[1], t[2], p), scale);
    let o3 = sign(orient2d(t[2], t[0], p), scale);
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
    let scale = scale_of(&[s, e, t[0], t[1], t[2]]).powf(2.0 / 3.0);
    point_in_triangle_2d(s2, t2, scale)
        || point_in_triangle_2d(e2, t2, scale)
        || (0..3).any(|i| segments_cross_2d(s2, e2, t2[i], t2[(i + 1) % 3], scale))
}

/// Whether two closed triangles with no shared vertex intersect.
pub fn triangles_intersect(a: [P3; 3], b: [P3; 3]) -> bool {
    let scale = scale_of(&[a[0], a[1], a[2], b[0], b[1], b[2]]);
    let db: [i8; 3] = std::array::from_fn(|i| sign(orient3d(a[0], a[1], a[2], b[i]), scale));
    if (db[0] > 0 && db[1] > 0 && db[2] > 0) || (db[0] < 0 && db[1] < 0 && db[2] < 0) {
        return false;
    }
    let da: [i8; 3] = std::array::from_fn(|i| sign(orient3d(b[0], b[1], b[2], a[i]), scale));
    if (da[0] > 0 && da[1] > 0 && da[2] > 0) || (da[0] < 0 && da[1] < 0 && da[2] < 0) {
        return false;
    }
    // Any intersection of two triangles is reached by an edge of one of them.
    (0..3).any(|i| segment_hits_triangle(a[i], a[(i + 1) % 3], b))
        || (0..3).any(|i| segment_hits_triangle(b[i], b[(i + 1) % 3], a))
}

/// Whether two triangles that share exactly the vertex `a[0] == b[0]` overlap
/// anywhere else.
pub fn triangles_intersect_sharing_vertex(a: [P3; 3], b: [P3; 3]) -> bool {
    // Away from the shared vertex, the intersection reaches an opposite edge.
    if segment_hits_triangle_open_at(b[1], b[2], a) || segment_hits_triangle_open_at(a[1], a[2], b)
    {
        return true;
    }
    // Coplanar fans can overlap without an opposite edge crossing (one sector
    // inside the other).
    let scale = scale_of(&[a[0], a[1], a[2], b[1], b[2]]);
    let d1 = sign(orient3d(a[0], a[1], a[2], b[1]), scale);
    let d2 = sign(orient3d(a[0], a[1], a[2], b[2]), scale);
    if d1 == 0 && d2 == 0 {
        let axis = dominant_axis(cross(sub(a[1], a[0]), sub(a[2], a[0])));
        let ta = [
            project2(a[0], axis),
            project2(a[1], axis),
            project2(a[2], axis),
        ];
        let tb = [
            project2(b[0], axis),
            project2(b[1], axis),
            project2(b[2], axis),
        ];
        let s2 = scale.powf(2.0 / 3.0);
        // Points slightly inside each edge from the shared vertex.
        let inner = |t: [[f64; 2]; 3], k: usize| {
            [
                t[0][0] + 1e-6 * (t[k][0] - t[0][0]) + 1e-6 * (t[3 - k][0] - t[0][0]),
                t[0][1] + 1e-6 * (t[k][1] - t[0][1]) + 1e-6 * (t[3 - k][1] - t[0][1]),
            ]
        };
        return point_in_triangle_2d(inner(tb, 1), ta, s2)
            || point_in_triangle_2d(inner(ta, 1), tb, s2);
    }
    false
}

/// Segment-triangle test that ignores contact at the triangle's vertex t[0]
/// (the shared vertex) by shrinking the triangle slightly towards its far edge.
fn segment_hits_triangle_open_at(s: P3, e: P3, t: [P3; 3]) -> bool {
    let shrink = 1e-9;
    let moved = [
        t[0][0] + shrink * (t[1][0] + t[2][0] - 2.0 * t[0][0]),
        t[0][1] + shrink * (t[1][1] + t[2][1] - 2.0 * t[0][1]),
        t[0][2] + shrink * (t[1][2] + t[2][2] - 2.0 * t[0][2]),
    ];
    segment_hits_triangle(s, e, [moved, t[1], t[2]])
}

/// Whether two triangles sharing the edge (a[0], a[1]) == (b[0], b[1]) in some
/// order fold onto each other (coplanar, third vertices on the same side).
pub fn triangles_fold_on_shared_edge(a: [P3; 3], b: [P3; 3]) -> bool {
    let scale = scale_of(&[a[0], a[1], a[2], b[2]]);
    if sign(orient3d(a[0], a[1], a[2], b[2]), scale) != 0 {
        return false;
    }
    let n = cross(sub(a[1], a[0]), sub(a[2], a[0]));
    let side = |p: P3| dot(cross(sub(a[1], a[0]), sub(p, a[0])), n);
    side(a[2]) * side(b[2]) > 0.0
}

/// Möller–Trumbore: distance along `dir` (not normalised) to triangle `t`, if the
/// ray from `origin` hits it at a parameter ≥ 0.
pub fn ray_triangle(origin: P3, dir: P3, t: [P3; 3]) -> Option<f64> {
    let e1 = sub(t[1], t[0]);
    let e2 = sub(t[2], t[0]);
    let p = cross(dir, e2);
    let det = dot(e1, p);
    let scale = dot(e1, e1).max(dot(e2, e2)) * dot(dir, dir).sqrt();
    if det.abs() <= 1e-14 * scale {
        return None;
    }
    let inv = 1.0 / det;
    let s = sub(origin, t[0]);
    let u = dot(s, p) * inv;
    if !(-1e-12..=1.0 + 1e-12).contains(&u) {
        return None;
    }
    let q = cross(s, e1);
    let v = dot(dir, q) * inv;
    if v < -1e-12 || u + v > 1.0 + 1e-12 {
        return None;
    }
    let t_hit = dot(e2, q) * inv;
    (t_hit >= 0.0).then_some(t_hit)
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: [P3; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

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
    fn folded_shared_edge() {
        let folded = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.5, 0.0]];
        assert!(triangles_fold_on_shared_edge(T, folded));
        let proper = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, -0.5, 0.0]];
        assert!(!triangles_fold_on_shared_edge(T, proper));
        let bent = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.5, 0.5]];
        assert!(!triangles_fold_on_shared_edge(T, bent));
    }

    #[test]
    fn ray_hits() {
        let t = ray_triangle([0.2, 0.2, 1.0], [0.0, 0.0, -2.0], T).unwrap();
        assert!((t - 0.5).abs() < 1e-12);
        assert!(ray_triangle([0.2, 0.2, 1.0], [0.0, 0.0, 1.0], T).is_none());
        assert!(ray_triangle([2.0, 2.0, 1.0], [0.0, 0.0, -1.0], T).is_none());
    }
}
