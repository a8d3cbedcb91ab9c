//! Prints the area and volume of the union of round cones of each SWC file
//! given, without meshing (developer tool: the reference's cost and spread).
//!
//! `cargo run --release --example union_measures -- FILE.swc...`
fn main() {
    for path in std::env::args().skip(1) {
        let m = neuromesh::Morphology::from_swc(&path).expect("swc");
        let t = std::time::Instant::now();
        let u = neuromesh::internals::measure::union::measure_morphology(&m);
        println!(
            "{path} area {:.6e} volume {:.6e} in {:.1} ms",
            u.area,
            u.volume,
            t.elapsed().as_secs_f64() * 1e3
        );
    }
}
