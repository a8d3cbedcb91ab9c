//! Meshes every SWC file in a folder and prints one line of checks per file:
//! components against trees, junctions by method, and self-intersections split
//! into construction defects and skeleton overlaps (developer tool).
//!
//! `cargo run --release --example survey -- [folder]` (default tests/data/real).

use std::time::Instant;

fn main() {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "tests/data/real".to_owned());
    // The folder's *.swc files, sorted, as `neuromesh batch` takes them.
    let files = neuromesh::batch::expand_inputs(&[dir.into()]).expect("SWC files");
    // NEUROMESH_RESOLUTION overrides the resolution (to weigh speed against accuracy).
    let mut params = neuromesh::Params::default();
    if let Some(r) = std::env::var("NEUROMESH_RESOLUTION")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        params = params.with_resolution(r);
    }
    println!(
        "{:<52} {:>6} {:>8} {:>7} {:>5} {:>5} {:>4} {:>5} {:>4} {:>4} {:>6} {:>6} {:>6} {:>6}",
        "file",
        "samples",
        "tris",
        "ms",
        "comp",
        "trees",
        "bad",
        "paper",
        "mov",
        "det",
        "constr",
        "skel",
        "dA%",
        "dV%"
    );
    let mut total = [0u64; 5];
    for f in files {
        let m = match neuromesh::Morphology::from_swc(&f) {
            Ok(m) => m,
            Err(e) => {
                println!("{e}");
                continue;
            }
        };
        let t = Instant::now();
        let mesh = neuromesh::mesh_morphology(&m, &params).expect("mesh");
        let ms = t.elapsed().as_secs_f64() * 1e3;
        let r = mesh.check_with(&m);
        let u = r
            .skeleton
            .and_then(|k| k.union)
            .expect("check_with measures the union");
        let bad = r.boundary_edges
            + r.nonmanifold_edges
            + r.nonmanifold_vertices
            + r.misoriented_edges
            + r.inward_components;
        let s = &mesh.stats;
        total[0] += u64::from(s.junctions_paper);
        total[1] += u64::from(s.junctions_moved);
        total[2] += u64::from(s.junctions_detached);
        total[3] += r.construction_intersections.unwrap_or(0) as u64;
        total[4] += r.skeleton_overlaps.unwrap_or(0) as u64;
        println!(
            "{:<52} {:>6} {:>8} {:>7.1} {:>5} {:>5} {:>4} {:>5} {:>4} {:>4} {:>6} {:>6} {:>+6.2} {:>+6.2}",
            f.file_name().unwrap().to_string_lossy(),
            m.len(),
            mesh.faces.len(),
            ms,
            r.components,
            m.trees().len(),
            bad,
            s.junctions_paper,
            s.junctions_moved,
            s.junctions_detached,
            r.construction_intersections.unwrap_or(0),
            r.skeleton_overlaps.unwrap_or(0),
            100.0 * (mesh.area() / u.area - 1.0),
            100.0 * (mesh.volume() / u.volume - 1.0),
        );
    }
    println!(
        "total junctions: {} paper, {} moved, {} detached; intersections: {} construction, {} skeleton",
        total[0], total[1], total[2], total[3], total[4]
    );
}
