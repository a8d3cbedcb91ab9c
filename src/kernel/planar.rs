//! Planar constrained triangulations with spade.
//!
//! Where a piece of surface can be seen as a height field over a plane, a
//! triangulation of its projection whose triangles do not overlap lifts to a
//! surface whose triangles cannot intersect each other: two triangles that met
//! in space would meet in projection too. Splicing uses this for the skirt
//! between a region's jagged rim and the contour above it, which no angular
//! merge can triangulate safely.
//!
//! Small polygons cut by a few chords (a face of the overlap pass crossed by
//! one intersection curve, the common case) are split and ear-clipped
//! instead ([`split_by_chains`], [`triangulate_polygon`]): for five to eight points
//! spade's bulk load costs more than the whole rest of the cut.

use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

/// Whether `p` lies inside the closed polygon `poly` (even–odd rule).
pub fn inside_polygon(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let mut inside = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// The inner triangles of `cdt`, built from `pts` in order, as
/// counter-clockwise vertex indices with their centroids: what each caller
/// needs to keep only the triangles inside its polygons.
pub fn triangles_with_centroids<'a>(
    cdt: &'a ConstrainedDelaunayTriangulation<Point2<f64>>,
    pts: &'a [[f64; 2]],
) -> impl Iterator<Item = ([usize; 3], [f64; 2])> + 'a {
    cdt.inner_faces().map(move |face| {
        let v = face.vertices().map(|h| h.fix().index());
        let p = v.map(|i| pts[i]);
        let c = [
            (p[0][0] + p[1][0] + p[2][0]) / 3.0,
            (p[0][1] + p[1][1] + p[2][1]) / 3.0,
        ];
        let area =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
        (if area > 0.0 { v } else { [v[0], v[2], v[1]] }, c)
    })
}

/// Triangulates the region between the simple polygon `outer` and the polygon
/// `inner` lying inside it, using only their vertices. Indices refer to `outer`
/// followed by `inner`; triangles are counter-clockwise. `None` if the loops are
/// not simple, touch each other, repeat a point or cannot be triangulated.
pub fn triangulate_annulus(outer: &[[f64; 2]], inner: &[[f64; 2]]) -> Option<Vec<[usize; 3]>> {
    let n_out = outer.len();
    let points: Vec<Point2<f64>> = outer
        .iter()
        .chain(inner)
        .map(|p| Point2::new(p[0], p[1]))
        .collect();
    if points.iter().any(|p| !(p.x.is_finite() && p.y.is_finite())) {
        return None;
    }
    let mut edges: Vec<[usize; 2]> = (0..n_out).map(|i| [i, (i + 1) % n_out]).collect();
    edges.extend((0..inner.len()).map(|i| [n_out + i, n_out + (i + 1) % inner.len()]));
    let mut conflict = false;
    let cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(points.clone(), edges, |_| {
            conflict = true
        })
        .ok()?;
    if conflict || cdt.num_vertices() != points.len() {
        return None;
    }
    let flat: Vec<[f64; 2]> = outer.iter().chain(inner).copied().collect();
    let tris: Vec<[usize; 3]> = triangles_with_centroids(&cdt, &flat)
        .filter(|(_, c)| inside_polygon(*c, outer) && !inside_polygon(*c, inner))
        .map(|(v, _)| v)
        .collect();
    // An annulus of n + m boundary vertices has exactly n + m triangles.
    (tris.len() == n_out + inner.len()).then_some(tris)
}

/// Splits the counter-clockwise polygon `0..n` (indices into a point list) by
/// `chains`: each runs from one polygon vertex to another through points
/// inside it, and no two cross. Each chain splits the piece holding both its
/// ends in two, both counter-clockwise. `None` when a chain's ends are not
/// both on exactly one piece (ends shared by two chains, a chain from a
/// vertex to itself).
pub fn split_by_chains(n: usize, chains: &[Vec<usize>]) -> Option<Vec<Vec<usize>>> {
    let mut pieces: Vec<Vec<usize>> = vec![(0..n).collect()];
    for chain in chains {
        let (s, t) = (*chain.first()?, *chain.last()?);
        if s == t || chain.len() < 2 {
            return None;
        }
        let mut holding = pieces
            .iter()
            .enumerate()
            .filter(|(_, p)| p.contains(&s) || p.contains(&t));
        let (k, _) = holding.next()?;
        if holding.next().is_some() {
            return None;
        }
        let piece = &pieces[k];
        let (i, j) = (
            piece.iter().position(|&v| v == s)?,
            piece.iter().position(|&v| v == t)?,
        );
        let inner = &chain[1..chain.len() - 1];
        let len = piece.len();
        // From s along the piece to t, then back along the chain; and from t
        // along the piece to s, then along the chain.
        let walk = |from: usize, to: usize| -> Vec<usize> {
            let mut out = Vec::new();
            let mut at = from;
            loop {
                out.push(piece[at]);
                if at == to {
                    return out;
                }
                at = (at + 1) % len;
            }
        };
        let mut first = walk(i, j);
        first.extend(inner.iter().rev());
        let mut second = walk(j, i);
        second.extend(inner.iter());
        pieces[k] = first;
        pieces.push(second);
    }
    Some(pieces)
}

/// Triangulates the simple counter-clockwise polygon `poly` (indices into
/// `pts`): its constrained Delaunay triangulation, as spade would give it,
/// by clipping ears and then flipping diagonals until each is locally
/// Delaunay (Lawson's flips; exact tests). Delaunay matters here: an ear
/// clipped blindly can join three nearly collinear points of a cut, a sliver
/// whose plane f32 rounding tilts through the faces around it. `None` if the
/// polygon is not simple (two edges that are not neighbours touch, a point
/// repeats) or an ear cannot be found.
pub fn triangulate_polygon(pts: &[[f64; 2]], poly: &[usize]) -> Option<Vec<[usize; 3]>> {
    let mut tris = ear_clip(pts, poly)?;
    // Each flip makes the triangulation strictly more Delaunay, so the loop
    // ends; the cap only guards against a bug.
    for _ in 0..tris.len() * tris.len() + 8 {
        let Some((i, j, a, b)) = illegal_diagonal(pts, &tris) else {
            return Some(tris);
        };
        let c = third(tris[i], a, b);
        let d = third(tris[j], b, a);
        tris[i] = [a, d, c];
        tris[j] = [d, b, c];
    }
    None
}

/// A diagonal shared by triangles `i` (as a, b, c) and `j` (as b, a, d)
/// with d inside the circle through a, b, c.
fn illegal_diagonal(pts: &[[f64; 2]], tris: &[[usize; 3]]) -> Option<(usize, usize, usize, usize)> {
    for (i, t) in tris.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            let c = t[(e + 2) % 3];
            let Some(j) = (i + 1..tris.len()).find(|&j| {
                let u = tris[j];
                (0..3).any(|k| u[k] == b && u[(k + 1) % 3] == a)
            }) else {
                continue;
            };
            let d = third(tris[j], b, a);
            if crate::kernel::predicates::in_circle(pts[a], pts[b], pts[c], pts[d]) {
                return Some((i, j, a, b));
            }
        }
    }
    None
}

/// The corner of `t` other than `a` and `b`.
fn third(t: [usize; 3], a: usize, b: usize) -> usize {
    t.into_iter().find(|&v| v != a && v != b).unwrap_or(a)
}

/// Triangulates the simple counter-clockwise polygon `poly` by clipping
/// ears, each time the best-shaped one (see [`triangulate_polygon`]).
fn ear_clip(pts: &[[f64; 2]], poly: &[usize]) -> Option<Vec<[usize; 3]>> {
    use crate::kernel::predicates::orient2d_sign;
    let n = poly.len();
    if n < 3 {
        return None;
    }
    // Simple: no two edges meet but neighbours, and neighbours only at
    // their common end (no fold back along one line).
    for i in 0..n {
        let (a, b) = (pts[poly[i]], pts[poly[(i + 1) % n]]);
        if a == b {
            return None;
        }
        for j in i + 1..n {
            let (c, d) = (pts[poly[j]], pts[poly[(j + 1) % n]]);
            let next = j == i + 1;
            let prev = i == 0 && j == n - 1;
            if next || prev {
                // Neighbours: the far end of one must not lie on the other.
                let (shared, p, q) = if next { (b, a, d) } else { (a, b, c) };
                if orient2d_sign(p, shared, q) == 0
                    && (p[0] - shared[0]) * (q[0] - shared[0])
                        + (p[1] - shared[1]) * (q[1] - shared[1])
                        > 0.0
                {
                    return None;
                }
            } else if crate::kernel::predicates::segments_meet_2d(a, b, c, d) {
                return None;
            }
        }
    }
    let mut left: Vec<usize> = poly.to_vec();
    let mut out = Vec::with_capacity(n - 2);
    while left.len() > 3 {
        let m = left.len();
        let mut best: Option<(f64, usize)> = None;
        for k in 0..m {
            let (u, v, w) = (left[(k + m - 1) % m], left[k], left[(k + 1) % m]);
            let (a, b, c) = (pts[u], pts[v], pts[w]);
            if orient2d_sign(a, b, c) <= 0 {
                continue;
            }
            let blocked = left.iter().any(|&x| {
                x != u
                    && x != v
                    && x != w
                    && crate::kernel::predicates::point_in_triangle_2d(pts[x], [a, b, c])
            });
            if blocked {
                continue;
            }
            let q = shape(a, b, c);
            if best.is_none_or(|(bq, _)| q > bq) {
                best = Some((q, k));
            }
        }
        let (_, k) = best?;
        let m = left.len();
        out.push([left[(k + m - 1) % m], left[k], left[(k + 1) % m]]);
        left.remove(k);
    }
    let [a, b, c] = [left[0], left[1], left[2]];
    if orient2d_sign(pts[a], pts[b], pts[c]) <= 0 {
        return None;
    }
    out.push([a, b, c]);
    Some(out)
}

/// Shape of a counter-clockwise triangle: twice its area over the sum of its
/// squared edges (largest for an equilateral one, 0 for a sliver).
fn shape(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    let d2 = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    let area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    area2 / (d2(a, b) + d2(b, c) + d2(c, a))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn circle(n: usize, r: f64, phase: f64) -> Vec<[f64; 2]> {
        (0..n)
            .map(|i| {
                let a = phase + std::f64::consts::TAU * i as f64 / n as f64;
                [r * a.cos(), r * a.sin()]
            })
            .collect()
    }

    #[test]
    fn annulus_of_a_jagged_rim_and_a_circle() {
        // A star-like rim that is not monotone in angle seen from the centre.
        let mut outer = circle(14, 2.0, 0.0);
        outer.insert(3, [1.5, 1.9]); // a notch that turns back
        let inner = circle(8, 0.7, 0.1);
        let tris = triangulate_annulus(&outer, &inner).expect("annulus");
        assert_eq!(tris.len(), outer.len() + inner.len());
        let all: Vec<[f64; 2]> = outer.iter().chain(&inner).copied().collect();
        let area: f64 = tris
            .iter()
            .map(|t| {
                let p = t.map(|i| all[i]);
                0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                    - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]))
            })
            .sum();
        let shoelace = |poly: &[[f64; 2]]| {
            0.5 * (0..poly.len())
                .map(|i| {
                    let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                    a[0] * b[1] - a[1] * b[0]
                })
                .sum::<f64>()
        };
        assert!((area - (shoelace(&outer) - shoelace(&inner))).abs() < 1e-9);
    }

    #[test]
    fn crossing_loops_are_refused() {
        let outer = circle(10, 1.0, 0.0);
        let inner = circle(6, 1.5, 0.2);
        assert!(triangulate_annulus(&outer, &inner).is_none());
    }

    /// Twice the signed area of triangle `t` of `pts`.
    fn area2(pts: &[[f64; 2]], t: [usize; 3]) -> f64 {
        let p = t.map(|i| pts[i]);
        (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0])
    }

    /// A triangle with two points on its edges (numbered around it: 0 corner,
    /// 1 on the first edge, 2 and 3 corners, 4 on the third edge) and a
    /// chain of `k` points between them inside, bent at random: a face cut
    /// by one intersection curve.
    fn cut_triangle(k: usize, seed: u64) -> (Vec<[f64; 2]>, Vec<usize>) {
        let mut rnd = seed;
        let mut unit = || {
            rnd = crate::kernel::hash::mix64(rnd);
            (rnd >> 11) as f64 / (1u64 << 53) as f64
        };
        let (a, b, c) = ([0.0, 0.0], [1.0, 0.1], [0.3, 0.9]);
        let lerp =
            |p: [f64; 2], q: [f64; 2], t: f64| [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
        let p = lerp(a, b, 0.2 + 0.6 * unit());
        let q = lerp(c, a, 0.2 + 0.6 * unit());
        let mut pts = vec![a, p, b, c, q];
        let mut chain = vec![1];
        for i in 0..k {
            // Along p → q, pushed sideways a little (stays inside).
            let on = lerp(p, q, (i as f64 + 1.0) / (k as f64 + 1.0));
            let g = lerp(on, [0.45, 0.35], 0.3 * unit());
            pts.push(g);
            chain.push(5 + i);
        }
        chain.push(4);
        (pts, chain)
    }

    /// spade's constrained Delaunay triangulation (without slivers) of polygon `0..nb` of
    /// `pts` with `chain` as constraints, as sorted triples.
    fn spade_cdt(pts: &[[f64; 2]], nb: usize, chain: &[usize]) -> Vec<[usize; 3]> {
        let points: Vec<Point2<f64>> = pts.iter().map(|p| Point2::new(p[0], p[1])).collect();
        let mut edges: Vec<[usize; 2]> = (0..nb).map(|i| [i, (i + 1) % nb]).collect();
        edges.extend(chain.windows(2).map(|w| [w[0], w[1]]));
        let cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
            ConstrainedDelaunayTriangulation::bulk_load_cdt(points, edges).expect("cdt");
        let outline = &pts[..nb];
        // A point rounded just inside an edge leaves a sliver between the
        // edge and the hull, whose centroid the float test may put inside.
        let mut out: Vec<[usize; 3]> = triangles_with_centroids(&cdt, pts)
            .filter(|(t, c)| inside_polygon(*c, outline) && area2(pts, *t) > 1e-12)
            .map(|(mut t, _)| {
                t.sort_unstable();
                t
            })
            .collect();
        out.sort_unstable();
        out
    }

    #[test]
    fn a_face_cut_by_a_curve_is_split_and_triangulated_as_spade_would() {
        for k in 0..6 {
            for seed in 0..40u64 {
                let (pts, chain) = cut_triangle(k, seed * 7 + k as u64);
                let pieces = split_by_chains(5, std::slice::from_ref(&chain)).expect("split");
                assert_eq!(pieces.len(), 2);
                let mut tris: Vec<[usize; 3]> = pieces
                    .iter()
                    .flat_map(|p| triangulate_polygon(&pts, p).expect("triangulated"))
                    .collect();
                assert!(tris.iter().all(|&t| area2(&pts, t) > 0.0), "{tris:?}");
                let total: f64 = tris.iter().map(|&t| area2(&pts, t)).sum();
                let outline: f64 = (0..5).map(|i| area2(&pts, [0, i, (i + 1) % 5])).sum();
                assert!((total - outline).abs() < 1e-12, "{total} against {outline}");
                assert_eq!(tris.len(), 5 + 2 * k - 2);
                for t in &mut tris {
                    t.sort_unstable();
                }
                tris.sort_unstable();
                assert_eq!(tris, spade_cdt(&pts, 5, &chain), "k {k} seed {seed}");
            }
        }
    }

    #[test]
    fn polygons_that_are_not_simple_are_refused() {
        let pts = [[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0]];
        // A bow tie, a point repeated, and a spike folding back along an edge.
        assert!(triangulate_polygon(&pts, &[0, 2, 1, 3]).is_some());
        assert!(triangulate_polygon(&pts, &[0, 1, 2, 3]).is_none());
        assert!(triangulate_polygon(&pts, &[0, 2, 1, 0, 3]).is_none());
        assert!(triangulate_polygon(&pts, &[0, 2, 4, 1, 3]).is_none());
        // Two chains from one end cannot both split the polygon.
        assert!(split_by_chains(4, &[vec![0, 2], vec![0, 4, 2]]).is_none());
        assert!(split_by_chains(4, &[vec![1, 1]]).is_none());
    }

    #[test]
    fn point_in_polygon() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(inside_polygon([0.5, 0.5], &sq));
        assert!(!inside_polygon([1.5, 0.5], &sq));
    }
}
