//! A union of parts can enclose a void: a cell's membrane has none, so the
//! mesher fills it (`mesher::drop_shells`) rather than leave an inward shell
//! that makes the mesh fail "outward".

use neuromesh::{Morphology, Params};

/// Six separate fat segments pointing away from the origin along ±x, ±y, ±z,
/// their inner end spheres (radius `0.95 d`, centres `d` from the origin)
/// leaving the origin uncovered. Every line from the origin passes within
/// `d·sqrt(2/3) = 0.82 d` of one of those centres, so the round cones (and
/// their inscribed polygons, which lose under 8 % of the radius here) close a
/// void around it.
fn six_around_a_void(d: f64) -> Morphology {
    let r = 0.95 * d;
    let mut xyz = Vec::new();
    let mut parents = Vec::new();
    for axis in 0..3 {
        for sign in [1.0, -1.0] {
            for dist in [d, 2.0 * d] {
                let mut p = [0.0; 3];
                p[axis] = sign * dist;
                parents.push(if dist == d { -1 } else { xyz.len() as i64 });
                xyz.push(p);
            }
        }
    }
    let n = xyz.len();
    let ids: Vec<i64> = (1..=n as i64).collect();
    Morphology::from_arrays(&ids, &vec![3; n], &xyz, &vec![r; n], &parents).expect("valid")
}

/// Winding number of `mesh` at `c`, counted along one ray (+1 for each face
/// the ray leaves through).
fn winding(mesh: &neuromesh::Mesh, c: [f64; 3]) -> i32 {
    let d = [0.577_2, 0.578_1, 0.577_0];
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let mut w = 0;
    for f in &mesh.faces {
        let t = f.map(|v| mesh.position(v as usize));
        let (e1, e2) = (sub(t[1], t[0]), sub(t[2], t[0]));
        let p = cross(d, e2);
        let det = dot(e1, p);
        if det.abs() < 1e-12 {
            continue;
        }
        let s = sub(c, t[0]);
        let u = dot(s, p) / det;
        let q = cross(s, e1);
        let v = dot(d, q) / det;
        if u < 0.0 || v < 0.0 || u + v > 1.0 || dot(e2, q) / det <= 0.0 {
            continue;
        }
        w += if dot(cross(e1, e2), d) > 0.0 { 1 } else { -1 };
    }
    w
}

#[test]
fn a_void_enclosed_by_crossing_branches_is_filled() {
    let m = six_around_a_void(10.0);
    let mesh = neuromesh::mesh_morphology(&m, &Params::default()).expect("meshes");
    let r = mesh.view().check(Some(&m));
    assert!(r.is_valid(), "{r}");
    assert_eq!(r.components, 1, "{r}");
    assert_eq!(r.self_intersections, 0, "{r}");
    // The void is inside the mesh now, and so is a point of the tubes.
    assert_eq!(winding(&mesh, [0.0; 3]), 1);
    assert_eq!(winding(&mesh, [15.0, 0.0, 0.0]), 1);
    assert_eq!(winding(&mesh, [40.0, 0.0, 0.0]), 0);
}
