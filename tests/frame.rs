//! Cells far from the coordinates' origin (atlas coordinates: MouseLight and
//! Allen CCF cells sit ~10⁴ µm out) mesh as they do at the origin.
//!
//! Vertices are f32; at 12,000 units their step is 0.001, 4 % of the
//! 0.025-unit processes of the glial cell used here: meshed in the file's
//! own frame, rounding would fold its thin processes into each other. Such a
//! cell is built around a point near its centre (`Mesh::origin`).

mod common;

use neuromesh::{Mesh, Morphology, Params, io};

const FAR: [f64; 3] = [12345.678, -23456.789, 5432.1];

fn glia() -> Morphology {
    Morphology::from_swc(common::real_dir().join("glia_type7_kannan_P1CS-31.CNG.swc"))
        .expect("reads")
}

fn assert_same_shape(near: &Mesh, far: &Mesh, what: &str) {
    let (ea, ev) = (
        far.area() / near.area() - 1.0,
        far.volume() / near.volume() - 1.0,
    );
    assert!(
        ea.abs() < 1e-3 && ev.abs() < 1e-3,
        "{what}: area {ea:+.2e}, volume {ev:+.2e} against the cell at the origin"
    );
}

#[test]
fn a_cell_far_from_the_origin_meshes_as_at_the_origin() {
    let near_cell = glia();
    let far_cell = near_cell.clone().translated(FAR);
    let params = Params::default();
    let near = neuromesh::mesh_morphology(&near_cell, &params).expect("meshes");
    let far = neuromesh::mesh_morphology(&far_cell, &params).expect("meshes");
    assert_eq!(
        near.origin, [0.0; 3],
        "a centred cell keeps its coordinates"
    );
    assert_ne!(
        far.origin, [0.0; 3],
        "a far cell is built around its centre"
    );
    let r = far.check_with(&far_cell);
    assert!(r.is_sound(), "{r}");
    assert_eq!(r.construction_intersections, Some(0), "{r}");
    assert_same_shape(&near, &far, "in memory");
    let (nt, ft) = (near.face_count() as f64, far.face_count() as f64);
    assert!((ft / nt - 1.0).abs() < 0.01, "{nt} and {ft} triangles");
    // Every vertex lies where it does in the mesh of the cell at the origin,
    // moved: compare the boxes of the absolute positions.
    let bounds = |m: &Mesh| {
        let p: Vec<[f64; 3]> = (0..m.vertex_count()).map(|i| m.position(i)).collect();
        neuromesh::internals::kernel::vector::bounds(&p)
    };
    let ((nlo, nhi), (flo, fhi)) = (bounds(&near), bounds(&far));
    for a in 0..3 {
        assert!(
            (flo[a] - nlo[a] - FAR[a]).abs() < 1e-3,
            "{a}: {flo:?} {nlo:?}"
        );
        assert!(
            (fhi[a] - nhi[a] - FAR[a]).abs() < 1e-3,
            "{a}: {fhi:?} {nhi:?}"
        );
    }
}

#[test]
fn obj_and_ply_keep_a_far_cell_exact_and_stl_warns() {
    let far_cell = glia().translated(FAR);
    let far = neuromesh::mesh_morphology(&far_cell, &Params::default()).expect("meshes");
    let dir = std::env::temp_dir().join(format!("neuromesh-frame-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for ext in ["obj", "ply", "stl"] {
        let path = dir.join(format!("far.{ext}"));
        io::write(&path, &far).expect("writes");
        let back = io::read(&path).expect("reads");
        assert_ne!(back.origin, [0.0; 3], "{ext}: read around its centre");
        let r = back.check();
        let format = io::Format::from_extension(ext).expect("format");
        assert_eq!(io::precision_warning(&far, format).is_some(), ext == "stl");
        if ext != "stl" {
            // OBJ and PLY hold f64 positions: every corner comes back to
            // within the f32 rounding of the local frame.
            assert!(r.is_valid(), "{ext}: {r}");
            assert_same_shape(&far, &back, ext);
            for (f, g) in far.faces.iter().zip(&back.faces).step_by(97) {
                for k in 0..3 {
                    let (p, q) = (far.position(f[k] as usize), back.position(g[k] as usize));
                    for a in 0..3 {
                        assert!((p[a] - q[a]).abs() < 1e-6, "{ext}: {p:?} {q:?}");
                    }
                }
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
