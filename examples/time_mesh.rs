//! Times meshing one SWC file, several times (developer tool for profiling).
fn main() {
    let path = std::env::args().nth(1).expect("swc");
    let reps: usize = std::env::args()
        .nth(2)
        .and_then(|r| r.parse().ok())
        .unwrap_or(1);
    let m = neuromesh::Morphology::from_swc(&path).expect("swc");
    for _ in 0..reps {
        let t = std::time::Instant::now();
        let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
        eprintln!(
            "{} triangles in {:.1} ms",
            mesh.faces.len(),
            t.elapsed().as_secs_f64() * 1e3
        );
    }
}
