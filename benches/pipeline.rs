//! Criterion benchmarks of the pipeline stages (filled in as stages land).
use criterion::{Criterion, criterion_group, criterion_main};

fn parse(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/y_bifurcation.swc");
    let bytes = std::fs::read(path).expect("fixture exists");
    c.bench_function("parse/y_bifurcation", |b| {
        b.iter(|| neuromesh::swc::SwcFile::parse(&bytes, "y.swc").expect("valid fixture"))
    });
}

criterion_group!(benches, parse);
criterion_main!(benches);
