//! Meshes every SWC file in a folder and prints one line of checks per file.
//!
//! `cargo run --release --example survey -- tests/data/real` (developer tool).

use std::time::Instant;

fn main() {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "tests/data/real".to_owned());
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("folder")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "swc"))
        .collect();
    files.sort();
    println!(
        "{:<55} {:>7} {:>9} {:>6} {:>5} {:>6} {:>6} {:>6} {:>8}",
        "file", "samples", "tris", "ms", "comp", "open", "nonman", "inward", "x-intra"
    );
    for f in files {
        let m = match neuromesh::Morphology::from_swc(&f) {
            Ok(m) => m,
            Err(e) => {
                println!("{e}");
                continue;
            }
        };
        let t = Instant::now();
        let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
        let ms = t.elapsed().as_secs_f64() * 1e3;
        let view = mesh.view();
        let r = mesh.check();
        let comp = neuromesh::check::face_components(&view);
        let pairs = neuromesh::check::self_intersections(&view);
        let intra = pairs
            .iter()
            .filter(|p| comp[p[0] as usize] == comp[p[1] as usize])
            .count();
        println!(
            "{:<55} {:>7} {:>9} {:>6.1} {:>5} {:>6} {:>6} {:>6} {:>8}",
            f.file_name().unwrap().to_string_lossy(),
            m.len(),
            mesh.faces.len(),
            ms,
            r.components,
            r.boundary_edges,
            r.nonmanifold_edges + r.nonmanifold_vertices,
            r.inward_components + r.misoriented_edges,
            intra
        );
    }
}
