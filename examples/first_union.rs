//! The overlap pass's first union of a file's constructed stage, fillers and
//! all, before any retry: crossing pairs found, pairs left in clusters it
//! could not cut, why, and the parts of those clusters (developer tool: why
//! did a cell lose fillers?).
//! `cargo run --release --example first_union -- FILE.swc...`
fn main() {
    let params = neuromesh::Params::default();
    for path in std::env::args().skip(1) {
        let m = neuromesh::Morphology::from_swc(&path).expect("swc");
        let built = neuromesh::internals::build::construct(
            &m,
            &params,
            neuromesh::internals::build::FIRST_REACH,
        )
        .expect("construction");
        let (mut mesh, owner) = built.into_mesh();
        let t = std::time::Instant::now();
        let r = neuromesh::internals::overlap::resolve(&mut mesh, owner);
        println!(
            "{path}: {} pairs, {} left ({}), {} parts in them, {:.0} ms",
            r.outcome.pairs,
            r.outcome.pairs_left,
            r.outcome.failure.unwrap_or("none"),
            r.left_parts.len(),
            t.elapsed().as_secs_f64() * 1e3
        );
    }
}
