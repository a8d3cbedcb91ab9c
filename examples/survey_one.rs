//! Meshes one SWC file and prints the check (developer tool).
fn main() {
    let path = std::env::args().nth(1).expect("swc");
    let m = neuromesh::Morphology::from_swc(&path).expect("swc");
    let t = std::time::Instant::now();
    let mesh = neuromesh::mesh_morphology(&m, &neuromesh::Params::default()).expect("mesh");
    eprintln!("meshed in {:.1} ms", t.elapsed().as_secs_f64() * 1e3);
    println!("{:?}", mesh.stats);
    let u = neuromesh::internals::measure::union::measure_morphology(&m);
    println!("union area {:.6e} volume {:.6e}", u.area, u.volume);
    println!("{}", mesh.check_with(&m));
}
