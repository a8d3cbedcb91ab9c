//! The soma: synthetic cells (a soma alone, with one, three and twelve
//! neurites, crowded trunks, trunks thicker than their soma) against the
//! union of their round cones.
//!
//! The reference area and volume are those of the exact union of the
//! skeleton's round cones with the soma as one sphere, integrated by seeded
//! Monte Carlo over each primitive's surface and volume
//! ([`neuromesh::internals::measure::union`], standard error about 0.2 %).

mod common;

use std::f64::consts::PI;

use neuromesh::{Mesh, Morphology, Params};

/// A soma of radius `r_soma` at the origin and one straight neurite per
/// direction: `n` samples 3 apart, radius tapering from 1.2 to 0.6, the first
/// one just outside the soma.
fn cell(r_soma: f64, dirs: &[[f64; 3]], n: usize) -> Morphology {
    let mut ids = vec![1i64];
    let mut types = vec![1];
    let mut xyz = vec![[0.0; 3]];
    let mut radii = vec![r_soma];
    let mut parents = vec![-1i64];
    for d in dirs {
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let u = [d[0] / len, d[1] / len, d[2] / len];
        for k in 0..n {
            let t = r_soma + 0.5 + 3.0 * k as f64;
            ids.push(ids.len() as i64 + 1);
            types.push(3);
            xyz.push([u[0] * t, u[1] * t, u[2] * t]);
            radii.push(1.2 - 0.6 * k as f64 / (n.max(2) - 1) as f64);
            parents.push(if k == 0 { 1 } else { ids.len() as i64 - 1 });
        }
    }
    Morphology::from_arrays(&ids, &types, &xyz, &radii, &parents).expect("valid cell")
}

/// Closed, manifold, outward, one component, no self-intersection at all,
/// area and volume within `tol` of the union of round cones.
fn assert_cell(m: &Morphology, tol: f64, what: &str) -> Mesh {
    let mesh = neuromesh::mesh_morphology(m, &Params::default()).expect("meshes");
    let r = mesh.check_with(m);
    assert!(r.is_sound(), "{what}\n{r}");
    assert_eq!(r.components, 1, "{what}\n{r}");
    assert_eq!(r.self_intersections, 0, "{what}\n{r}");
    let u = neuromesh::internals::measure::union::measure_morphology(m);
    let (ea, ev) = (mesh.area() / u.area - 1.0, mesh.volume() / u.volume - 1.0);
    assert!(
        ea.abs() < tol && ev.abs() < tol,
        "{what}: area {ea:+.4}, volume {ev:+.4} against the union"
    );
    mesh
}

/// Every trunk joined: by the soma's triangulation or spliced (these cells
/// have no other branch points).
fn assert_trunks_joined(mesh: &Mesh, trunks: u32) {
    let s = &mesh.stats;
    assert_eq!(
        s.soma_trunks + s.junctions_paper + s.junctions_moved,
        trunks,
        "{s:?}"
    );
}

#[test]
fn a_soma_alone_is_a_sphere_within_one_percent() {
    let m = cell(4.0, &[], 0);
    let mesh = assert_cell(&m, 0.01, "soma alone");
    let (a, v) = (4.0 * PI * 16.0, 4.0 / 3.0 * PI * 64.0);
    assert!((mesh.area() / a - 1.0).abs() < 0.01);
    assert!((mesh.volume() / v - 1.0).abs() < 0.01);
}

#[test]
fn a_soma_with_one_neurite() {
    let m = cell(4.0, &[[1.0, 0.2, 0.1]], 8);
    let mesh = assert_cell(&m, 0.03, "one neurite");
    assert_eq!(mesh.stats.soma_trunks, 1);
}

#[test]
fn a_soma_with_three_neurites() {
    let m = cell(
        4.0,
        &[[1.0, 0.0, 0.0], [-0.5, 0.8, 0.1], [-0.4, -0.7, 0.5]],
        8,
    );
    let mesh = assert_cell(&m, 0.03, "three neurites");
    assert_eq!(mesh.stats.soma_trunks, 3);
}

/// Twelve trunks spread over a soma five times as thick as they are. Measured:
/// area +2.3 %, volume −5.1 %. The union's round cone from the soma's centre
/// to each trunk's first sample is a wide fillet around the trunk's base; the
/// mesh bridges radially from the soma to the trunk's first contour outside
/// it, which leaves the fillet's wedge out, twelve times.
#[test]
fn a_soma_with_twelve_neurites() {
    let dirs: Vec<[f64; 3]> = neuromesh::internals::build::soma::fibonacci(12)
        .iter()
        .map(|u| u.to_array())
        .collect();
    let m = cell(6.0, &dirs, 8);
    let mesh = assert_cell(&m, 0.06, "twelve neurites");
    assert_trunks_joined(&mesh, 12);
}

/// Twelve trunks on one soma point, all within 50° of one direction (as on the
/// spinal motoneurons): footprints that would overlap are spliced instead.
/// Still one closed surface without self-intersections; the volume falls short
/// of the union (measured −9.2 %, area +0.6 %) because a spliced trunk starts only where it
/// clears its neighbours, and the part of its cone outside theirs is lost.
#[test]
fn a_soma_with_twelve_crowded_neurites() {
    let dirs: Vec<[f64; 3]> = (0..12)
        .map(|k| {
            let (ring, a) = if k < 4 {
                (0.35, k as f64 * PI / 2.0)
            } else {
                (0.8, (k - 4) as f64 * PI / 4.0 + 0.3)
            };
            [ring * a.cos(), ring * a.sin(), 1.0]
        })
        .collect();
    let m = cell(4.0, &dirs, 8);
    let mesh = assert_cell(&m, 0.12, "twelve crowded neurites");
    assert_trunks_joined(&mesh, 12);
}

/// A neurite thicker than its soma still meshes, joined to it.
#[test]
fn a_neurite_thicker_than_the_soma() {
    let ids = [1, 2, 3, 4];
    let xyz = [[0.0; 3], [3.0, 0.0, 0.0], [8.0, 0.0, 0.0], [14.0, 0.0, 0.0]];
    let m = Morphology::from_arrays(
        &ids,
        &[1, 3, 3, 3],
        &xyz,
        &[1.0, 2.5, 2.5, 2.0],
        &[-1, 1, 2, 3],
    )
    .expect("valid");
    assert_cell(&m, 0.03, "thick neurite");
}

/// A 3-point soma rounded to whole units is no longer recognised (its points
/// stand 7 and 6 from the centre sample, radius 6.5): the soma is the
/// contour's sphere, radius 4.44, and the trunk's first sample's sphere,
/// radius 6.5, reaches out of it all round. The tube starts flat at that
/// sample; the trunk's filler, taking the whole first cone, holds the half of
/// the sphere behind it. Here the mesh lacked 10.3 % of the union's volume
/// without it and lacks 0.8 % with it; a fly cell rounded so (alxP) went from
/// -28.5 % to -17.7 %, the rest lost on its thin neurites.
#[test]
fn a_trunk_sample_wider_than_the_soma() {
    let ids = [1, 2, 3, 4, 5, 6];
    let xyz = [
        [0.0, 0.0, 0.0],
        [0.0, 7.0, 0.0],
        [0.0, -6.0, 0.0],
        [0.0, 8.0, 0.0],
        [0.0, 20.0, 0.0],
        [0.0, 30.0, 0.0],
    ];
    let m = Morphology::from_arrays(
        &ids,
        &[1, 1, 1, 3, 3, 3],
        &xyz,
        &[6.5, 6.5, 6.5, 1.0, 1.0, 0.8],
        &[-1, 1, 1, 1, 4, 5],
    )
    .expect("valid");
    assert_cell(&m, 0.03, "trunk sample wider than the soma");
}

/// A 3-point soma whose radius (6.6) does not match its points (2.6 from
/// the centre) is taken as a contour, of radius 1.76, and a thin trunk
/// starts 3.9 from the centre sample, deep inside that sample's sphere,
/// which the union holds whole. The trunk's filler takes the whole first
/// cone; its last contour, widened to the sphere's section there (radius
/// 5.3), ends flat: domed, it stood out of the sphere and the mesh came
/// 11.1 % over the union's volume (+2.7 % flat; the area, +5.1 %, is not
/// asserted within 3 %).
#[test]
fn a_thin_trunk_deep_inside_its_soma_samples_sphere() {
    let xyz = [
        [0.0, 0.0, 0.0],
        [-0.37, 2.6, 0.0],
        [0.37, -2.61, 0.0],
        [-3.94, 0.55, 0.0],
        [-7.42, -0.36, 0.0],
        [-11.09, 2.22, 0.0],
        [-15.0, 3.0, 0.0],
    ];
    let m = Morphology::from_arrays(
        &[1, 2, 3, 4, 5, 6, 7],
        &[1, 1, 1, 7, 7, 7, 7],
        &xyz,
        &[6.6112, 6.6112, 6.6112, 0.0625, 0.0625, 0.1125, 0.1125],
        &[-1, 1, 1, 1, 4, 5, 6],
    )
    .expect("valid");
    let mesh = neuromesh::mesh_morphology(&m, &Params::default()).expect("meshes");
    let r = mesh.check_with(&m);
    assert!(r.is_sound(), "{r}");
    assert_eq!(r.components, 1, "{r}");
    assert_eq!(r.self_intersections, 0, "{r}");
    let u = neuromesh::internals::measure::union::measure_morphology(&m);
    let (ea, ev) = (mesh.area() / u.area - 1.0, mesh.volume() / u.volume - 1.0);
    assert!(
        ev.abs() < 0.03 && ea.abs() < 0.06,
        "area {ea:+.4}, volume {ev:+.4}"
    );
}

/// The check without the union of round cones reports all the full check
/// does but the union.
#[test]
fn the_check_without_the_union_leaves_out_only_the_union() {
    let m = cell(5.0, &[[1.0, 0.0, 0.0], [0.0, 1.0, 0.2]], 6);
    let mesh = neuromesh::mesh_morphology(&m, &Params::default()).expect("meshes");
    let full = mesh.view().check(Some(&m));
    let mut fast = mesh.view().check_without_union(Some(&m));
    let union = full.skeleton.and_then(|s| s.union);
    assert!(union.is_some(), "{full}");
    let skeleton = fast.skeleton.as_mut().expect("skeleton measures");
    assert_eq!(skeleton.union, None);
    skeleton.union = union;
    assert_eq!(fast, full);
}
