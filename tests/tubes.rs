//! Neurite tubes: simple shapes against their analytic area and volume, and
//! random branches whose every piece must be sound. (Every branch of every
//! real file is checked by `tests/corpus.rs`.)

mod common;

use std::f64::consts::PI;

use neuromesh::{Mesh, Morphology, Params};
use proptest::prelude::*;

/// A single unbranched path (no soma) from points and radii.
fn path(points: &[[f64; 3]], radii: &[f64]) -> Morphology {
    let n = points.len();
    let ids: Vec<i64> = (1..=n as i64).collect();
    let parents: Vec<i64> = (0..n as i64).map(|i| if i == 0 { -1 } else { i }).collect();
    Morphology::from_arrays(&ids, &vec![3; n], points, radii, &parents).expect("valid path")
}

fn mesh(m: &Morphology) -> Mesh {
    neuromesh::mesh_morphology(m, &Params::default()).expect("meshes")
}

/// Closed, manifold, outward, no degenerate or duplicate faces.
fn assert_closed(mesh: &Mesh, what: &str) {
    let r = mesh.view().check_topology();
    assert!(r.is_closed(), "{what}: not closed\n{r}");
    assert!(r.is_manifold(), "{what}: not manifold\n{r}");
    assert!(r.is_outward(), "{what}: not outward\n{r}");
    assert_eq!(r.degenerate_faces, 0, "{what}\n{r}");
    assert_eq!(r.duplicate_faces, 0, "{what}\n{r}");
}

/// Closed as above and free of any self-intersection.
fn assert_sound(mesh: &Mesh, what: &str) {
    assert_closed(mesh, what);
    let r = mesh.check();
    assert_eq!(r.self_intersections, 0, "{what}\n{r}");
    assert_eq!(r.components, 1, "{what}\n{r}");
}

fn rel(got: f64, want: f64) -> f64 {
    got / want - 1.0
}

/// Capsule: cylinder of radius 1 and length 20 with hemispherical ends.
/// Measured at default resolution: area +0.83 %, volume −0.74 %.
#[test]
fn straight_cylinder_within_one_percent() {
    let m = path(&[[0.0; 3], [10.0, 0.0, 0.0], [20.0, 0.0, 0.0]], &[1.0; 3]);
    let mesh = mesh(&m);
    assert_sound(&mesh, "cylinder");
    let area = 2.0 * PI * 20.0 + 4.0 * PI;
    let volume = PI * 20.0 + 4.0 / 3.0 * PI;
    let (ea, ev) = (rel(mesh.area(), area), rel(mesh.volume(), volume));
    assert!(
        ea.abs() < 0.01 && ev.abs() < 0.01,
        "area {ea:+.4}, volume {ev:+.4}"
    );
}

/// The round cone from radius 2 to radius 1 over length 20: frustum tangent to
/// both end spheres plus the spheres' outer caps.
/// Measured at default resolution: area +0.75 %, volume −0.92 %.
#[test]
fn cone_within_one_percent() {
    let m = path(
        &[[0.0; 3], [10.0, 0.0, 0.0], [20.0, 0.0, 0.0]],
        &[2.0, 1.5, 1.0],
    );
    let mesh = mesh(&m);
    assert_sound(&mesh, "cone");
    let (r1, r2, l) = (2.0f64, 1.0f64, 20.0f64);
    let s = (r1 - r2) / l; // sine of the half-angle of the tangent cone
    let c = (1.0 - s * s).sqrt();
    let (h1, h2) = (r1 * s, r2 * s); // tangent circles' offsets towards the thin end
    let (a1, a2) = (r1 * c, r2 * c); // tangent circles' radii
    let len = l - h1 + h2;
    let lateral = PI * (a1 + a2) * ((a1 - a2).powi(2) + len * len).sqrt();
    let caps = 2.0 * PI * r1 * (r1 + h1) + 2.0 * PI * r2 * (r2 - h2);
    let cap_volume = |r: f64, h: f64| PI * h * h * (3.0 * r - h) / 3.0;
    let volume = PI * len / 3.0 * (a1 * a1 + a1 * a2 + a2 * a2)
        + cap_volume(r1, r1 + h1)
        + cap_volume(r2, r2 - h2);
    let (ea, ev) = (rel(mesh.area(), lateral + caps), rel(mesh.volume(), volume));
    assert!(
        ea.abs() < 0.01 && ev.abs() < 0.01,
        "area {ea:+.4}, volume {ev:+.4}"
    );
}

/// A quarter circle of radius 10 (a point every 3°) with a tube of radius 1:
/// Pappus' theorem for the torus section plus two hemispheres.
/// Measured at default resolution: area +0.83 %, volume −0.74 %.
#[test]
fn bent_tube_within_one_percent() {
    let pts: Vec<[f64; 3]> = (0..=30)
        .map(|i| {
            let t = f64::from(i).to_radians() * 3.0;
            [10.0 * t.cos(), 10.0 * t.sin(), 0.0]
        })
        .collect();
    let m = path(&pts, &vec![1.0; pts.len()]);
    let mesh = mesh(&m);
    assert_sound(&mesh, "bent tube");
    let theta = PI / 2.0;
    let area = 2.0 * PI * 10.0 * theta + 4.0 * PI;
    let volume = PI * 10.0 * theta + 4.0 / 3.0 * PI;
    let (ea, ev) = (rel(mesh.area(), area), rel(mesh.volume(), volume));
    assert!(
        ea.abs() < 0.01 && ev.abs() < 0.01,
        "area {ea:+.4}, volume {ev:+.4}"
    );
}

#[test]
fn vertex_labels_are_samples_of_the_branch() {
    let m = path(
        &[
            [0.0; 3],
            [5.0, 0.0, 0.0],
            [10.0, 1.0, 0.0],
            [15.0, 3.0, 0.0],
        ],
        &[1.0, 0.8, 0.6, 0.5],
    );
    let mesh = mesh(&m);
    assert_eq!(mesh.vertex_sample.len(), mesh.vertices.len());
    for (v, &s) in mesh.vertices.iter().zip(&mesh.vertex_sample) {
        let p = m.positions()[s as usize];
        let d = ((f64::from(v[0]) - p[0]).powi(2)
            + (f64::from(v[1]) - p[1]).powi(2)
            + (f64::from(v[2]) - p[2]).powi(2))
        .sqrt();
        // Within the sample's radius (plus polygon correction) and half a segment.
        assert!(
            d <= 1.1 * m.radii()[s as usize] + 2.7,
            "vertex {v:?} far from its sample {s}"
        );
    }
}

/// A random unbranched path: steps of random length and direction (hairpins
/// included), radii spanning three orders of magnitude, and near-duplicates.
fn random_path() -> impl Strategy<Value = (Vec<[f64; 3]>, Vec<f64>)> {
    (3usize..40, any::<u64>()).prop_map(|(n, seed)| {
        let mut rng = seed;
        let mut next = move || {
            // xorshift64*: deterministic per case, enough for geometry.
            rng ^= rng >> 12;
            rng ^= rng << 25;
            rng ^= rng >> 27;
            (rng.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut pts = vec![[0.0f64; 3]];
        let mut radii = vec![0.01 + 10.0 * next()];
        let mut dir = [1.0, 0.0, 0.0];
        for _ in 1..n {
            let kind = next();
            let step = if kind < 0.1 {
                1e-7 // near-duplicate point
            } else {
                0.05 + 8.0 * next()
            };
            if kind > 0.85 {
                dir = [-dir[0], -dir[1], -dir[2]]; // hairpin
            } else {
                for c in &mut dir {
                    *c += 1.2 * (next() - 0.5);
                }
                let len = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2])
                    .sqrt()
                    .max(1e-9);
                for c in &mut dir {
                    *c /= len;
                }
            }
            let last = pts[pts.len() - 1];
            pts.push([
                last[0] + step * dir[0],
                last[1] + step * dir[1],
                last[2] + step * dir[2],
            ]);
            // Radii from 0.01 to 10: three orders of magnitude.
            radii.push(0.01 * 1000f64.powf(next()));
        }
        (pts, radii)
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]

    #[test]
    fn random_branches_are_sound((pts, radii) in random_path()) {
        let m = path(&pts, &radii);
        let mesh = mesh(&m);
        prop_assert!(!mesh.faces.is_empty());
        let what = format!("{pts:?} {radii:?}");
        common::assert_pieces_sound(&m, &what);
        // Where the path folds back through itself the spliced surface may
        // cross its own earlier part: that is the union's business (the splice's
        // tests), not the tube's.
        assert_closed(&mesh, &what);
    }
}

/// The widening cap decides these files' volume: two FlyWire EM traces that
/// jitter below their radius scale (−3.60 and −4.34 % of the union of round
/// cones' volume with the tubes widened at most 1.15, −2.15 and −1.28 % at
/// 1.25), and a fly medulla cell whose fillers crowd its thick trunks at
/// 1.25 past what the overlap pass cuts (−16.08 % with the fillers given up;
/// built again at 1.15, +1.13 %). Each comes within 3 % and uncrossed.
#[test]
fn the_sweep_cap_keeps_jittering_traces_and_crowded_trunks_within_three_percent() {
    for name in [
        "drosophila_flywire_720575940661139073.swc",
        "drosophila_flywire_720575940661205633.swc",
        "drosophila_medulla_L1_chklovskii_209.swc",
    ] {
        let m = Morphology::from_swc(common::real_dir().join(name)).expect("reads");
        let mesh = mesh(&m);
        assert_eq!(mesh.stats.overlap_pairs_left, 0, "{name}");
        let r = mesh.view().check(Some(&m));
        let union = r
            .skeleton
            .and_then(|k| k.union)
            .expect("a morphology's check has the union");
        let dv = 100.0 * (r.volume / union.volume - 1.0);
        assert!(dv.abs() <= 3.0, "{name}: volume {dv:+.2} % of the union's");
    }
}

/// A trace of long runs joined by short sharp steps (30-long runs, 3-high
/// steps, radius 0.5) stays on the union of its round cones: the spline
/// through the points would bulge off each run by more than the radius,
/// and is held within a tenth of it of the chords
/// (`spline::DEVIATION_BOUND`).
#[test]
fn long_runs_between_sharp_steps_stay_on_the_union_of_round_cones() {
    let mut pts = Vec::new();
    for k in 0..4 {
        let (x, y) = (30.0 * f64::from(k), 3.0 * f64::from(k));
        pts.push([x, y, 0.0]);
        pts.push([x + 30.0, y, 0.0]);
    }
    let r = 0.5;
    let m = path(&pts, &vec![r; pts.len()]);
    let mesh = mesh(&m);
    assert_sound(&mesh, "staircase of long runs");
    let cones = m.round_cones();
    let worst = (0..mesh.vertices.len())
        .map(|v| {
            let p = glam::DVec3::from_array(mesh.position(v));
            cones.iter().map(|c| c.sdf(p)).fold(f64::INFINITY, f64::min)
        })
        .fold(f64::NEG_INFINITY, f64::max);
    // The contours' polygons reach 2.3 % of the radius out (their radius
    // is corrected to the circle's cross-section); the chord bound adds 10 %.
    assert!(worst <= 0.15 * r, "a vertex {worst:.4} outside the union");
    let r = mesh.view().check(Some(&m));
    let union = r.skeleton.and_then(|k| k.union).expect("the union");
    let (da, dv) = (rel(r.area, union.area), rel(r.volume, union.volume));
    assert!(
        da.abs() < 0.03 && dv.abs() < 0.03,
        "area {da:+.4}, volume {dv:+.4} of the union's"
    );
}

#[test]
fn a_built_stage_keeps_the_first_rings_of_each_piece() {
    // A helix: it bends everywhere, so no stretch is thinned out, and its
    // tube has far more contours than a stage keeps.
    let points: Vec<[f64; 3]> = (0..400)
        .map(|i| {
            let t = f64::from(i) * 0.2;
            [10.0 * t.cos(), 10.0 * t.sin(), 0.8 * t]
        })
        .collect();
    let m = path(&points, &vec![0.5; points.len()]);
    let stage = common::build_tubes(&m);
    let kept = neuromesh::internals::build::tube::KEPT_RINGS;
    let tris = &stage.surface.tris;
    // The bands are all kept: one per contour the piece was built with.
    assert!(
        stage.tubes.iter().any(|t| t.bands.len() > kept),
        "a piece longer than the rings kept"
    );
    for t in &stage.tubes {
        assert!(t.rings.len() <= kept && !t.rings.is_empty());
        // The rings kept are the first: band i joins ring i to ring i + 1.
        for (i, pair) in t.rings.windows(2).enumerate() {
            let on = |k: u32, r: &neuromesh::internals::build::tube::Ring| {
                (r.first..r.first + r.m).contains(&k)
            };
            for f in t.bands[i]..t.bands[i + 1] {
                let face = tris[f as usize];
                assert!(
                    face.iter().all(|&k| on(k, &pair[0]) || on(k, &pair[1])),
                    "band {i} of a piece joins its rings {i} and {}",
                    i + 1
                );
            }
        }
    }
}
