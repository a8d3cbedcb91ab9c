//! A union of parts can enclose a void: a cell's membrane has none, so the
//! mesher fills it (`pipeline::shells`) rather than leave an inward shell
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
/// the ray leaves through), with the crate's own ray–triangle test.
fn winding(mesh: &neuromesh::Mesh, c: [f64; 3]) -> i32 {
    let d = [0.577_2, 0.578_1, 0.577_0];
    let mut w = 0;
    for f in &mesh.faces {
        let t = f.map(|v| mesh.position(v as usize));
        let (hit, near) = neuromesh::internals::kernel::predicates::ray_triangle_near(c, d, t);
        assert!(!near, "the ray passes near a face's border: pick another");
        if hit.is_some_and(|s| s > 0.0) {
            let e = |i: usize| [t[i][0] - t[0][0], t[i][1] - t[0][1], t[i][2] - t[0][2]];
            let (e1, e2) = (e(1), e(2));
            let n = [
                e1[1] * e2[2] - e1[2] * e2[1],
                e1[2] * e2[0] - e1[0] * e2[2],
                e1[0] * e2[1] - e1[1] * e2[0],
            ];
            w += if n[0] * d[0] + n[1] * d[1] + n[2] * d[2] > 0.0 {
                1
            } else {
                -1
            };
        }
    }
    w
}

#[test]
fn a_void_enclosed_by_crossing_branches_is_filled() {
    let m = six_around_a_void(10.0);
    let mesh = neuromesh::mesh_morphology(&m, &Params::default()).expect("meshes");
    let r = mesh.view().check(Some(&m));
    assert!(r.is_sound(), "{r}");
    assert_eq!(r.components, 1, "{r}");
    assert_eq!(r.self_intersections, 0, "{r}");
    // The void is inside the mesh now, and so is a point of the tubes.
    assert_eq!(winding(&mesh, [0.0; 3]), 1);
    assert_eq!(winding(&mesh, [15.0, 0.0, 0.0]), 1);
    assert_eq!(winding(&mesh, [40.0, 0.0, 0.0]), 0);
}
