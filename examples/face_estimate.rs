//! The triangles [`neuromesh::estimate`] expects against those the mesh has,
//! per file (developer tool, for the budget's documentation):
//! `cargo run --release --example face_estimate -- FILE.swc...`.
fn main() {
    let params = neuromesh::Params::default();
    println!("file\testimate\ttriangles\tratio\tmax length/radius\testimate ms");
    for path in std::env::args().skip(1) {
        let m = match neuromesh::Morphology::from_swc(&path) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("{e}");
                continue;
            }
        };
        let t = std::time::Instant::now();
        let e = neuromesh::estimate(&m, &params);
        let ms = t.elapsed().as_secs_f64() * 1e3;
        let faces = neuromesh::mesh_morphology(&m, &params).map_or(0, |mesh| mesh.faces.len());
        let name = std::path::Path::new(&path)
            .file_name()
            .map_or(path.clone(), |n| n.to_string_lossy().into_owned());
        println!(
            "{name}\t{:.0}\t{faces}\t{:.2}\t{:.1}\t{ms:.2}",
            e.faces,
            e.faces / faces.max(1) as f64,
            e.length_over_radius
        );
    }
}
