//! Criterion benchmarks of the pipeline stages on real files of several sizes.
//!
//! Throughput is in samples (SWC points) per second; the triangle counts per
//! file are printed once so triangles per second follow from the timings.
//! Run with `cargo bench --bench pipeline`; results are recorded in
//! `benches/README.md`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use neuromesh::{Morphology, Params};

/// Real files from the test corpus: a small, a median, and the largest ones.
const FILES: [&str; 4] = [
    "rat_CA1_CCK_interneuron_cck7632.CNG.swc",
    "mouse_V1_Scnn1a_allen_177300.swc",
    "mouse_allen_test_swc_26k.swc",
    "rat_neocortex_interneuron_MTC260800D-IDA.CNG.swc",
];

fn path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/real")
        .join(name)
}

fn parse(c: &mut Criterion) {
    let mut g = c.benchmark_group("parse");
    for name in FILES {
        let bytes = std::fs::read(path(name)).expect("fixture exists");
        let n = neuromesh::swc::SwcFile::parse(&bytes, name)
            .expect("valid")
            .samples
            .len();
        g.throughput(Throughput::Elements(n as u64));
        g.bench_with_input(BenchmarkId::from_parameter(name), &bytes, |b, bytes| {
            b.iter(|| {
                let f = neuromesh::swc::SwcFile::parse(black_box(bytes), name).expect("valid");
                Morphology::from_file(f).expect("valid")
            })
        });
    }
    g.finish();
}

fn tubes(c: &mut Criterion) {
    let mut g = c.benchmark_group("mesh");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for name in FILES {
        let m = Morphology::from_swc(path(name)).expect("valid");
        let tris = neuromesh::mesh_morphology(&m, &Params::default())
            .expect("meshes")
            .faces
            .len();
        eprintln!("{name}: {} samples, {tris} triangles", m.len());
        g.throughput(Throughput::Elements(m.len() as u64));
        g.bench_with_input(BenchmarkId::from_parameter(name), &m, |b, m| {
            b.iter(|| neuromesh::mesh_morphology(black_box(m), &Params::default()).expect("meshes"))
        });
    }
    g.finish();
}

criterion_group!(benches, parse, tubes);
criterion_main!(benches);
