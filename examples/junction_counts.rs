//! Sums the junction counts by method over SWC files (developer tool).
//! `cargo run --release --example junction_counts -- FILE...`
fn main() {
    let (mut paper, mut moved, mut fallback, mut detached) = (0u64, 0u64, 0u64, 0u64);
    for path in std::env::args().skip(1) {
        let m = neuromesh::Morphology::from_swc(&path).expect("swc");
        let s = neuromesh::mesh_morphology(&m, &neuromesh::Params::default())
            .expect("mesh")
            .stats;
        if s.junctions_fallback + s.junctions_detached > 0 {
            println!(
                "{path}: {} fallback, {} detached",
                s.junctions_fallback, s.junctions_detached
            );
        }
        paper += u64::from(s.junctions_paper);
        moved += u64::from(s.junctions_moved);
        fallback += u64::from(s.junctions_fallback);
        detached += u64::from(s.junctions_detached);
    }
    let all = (paper + moved + fallback + detached).max(1) as f64;
    println!(
        "paper {paper} ({:.1} %), moved {moved} ({:.1} %), fallback {fallback} ({:.2} %), detached {detached}",
        100.0 * paper as f64 / all,
        100.0 * moved as f64 / all,
        100.0 * fallback as f64 / all
    );
}
