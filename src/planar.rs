//! Planar constrained triangulations with spade.
//!
//! Where a piece of surface can be seen as a height field over a plane, a
//! triangulation of its projection whose triangles do not overlap lifts to a
//! surface whose triangles cannot intersect each other: two triangles that met
//! in space would meet in projection too. Splicing uses this for the skirt
//! between a region's jagged rim and the contour above it, which no angular
//! merge can triangulate safely.

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

    #[test]
    fn point_in_polygon() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert!(inside_polygon([0.5, 0.5], &sq));
        assert!(!inside_polygon([1.5, 0.5], &sq));
    }
}
