//! Criterion benchmarks of every pipeline stage, and end to end, on real files
//! of several sizes from the repository's test data.
//!
//! Stages: `parse` (SWC bytes to a cleaned morphology), `resample` (branch
//! identification and Catmull-Rom tracks with their contour sizes), `tubes`
//! (the whole tube stage: resampling, adaptive contours, contour connection,
//! caps), `soma` (sphere point sets and their constrained Delaunay
//! triangulations), `splice` (every junction), `overlaps` (the union where
//! parts of the spliced mesh cross), `write_obj` / `write_ply` (into
//! memory), and `end_to_end` (file on disk to mesh in memory). Throughput is in
//! SWC samples per second for `parse`, `resample` and `tubes`, and in output
//! triangles per second for the others.
//!
//! Run single-threaded, as the figures in `benches/README.md` were taken:
//! `RAYON_NUM_THREADS=1 cargo bench --bench pipeline`.

use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use neuromesh::internals::build::{self, FIRST_REACH, plan, tubes};
use neuromesh::internals::{overlap, skeleton};
use neuromesh::{Mesh, Morphology, Params};

/// Real files from the test corpus: small, median, a big Purkinje cell, and
/// the largest.
const FILES: [&str; 4] = [
    "rat_CA1_CCK_interneuron_cck7632.CNG.swc",
    "mouse_V1_Scnn1a_allen_177300.swc",
    "purkinje_martone_alxP.CNG.swc",
    "rat_neocortex_interneuron_MTC260800D-IDA.CNG.swc",
];

fn path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/real")
        .join(name)
}

/// Each file with its morphology and finished mesh (for triangle counts and
/// the writers).
fn fixtures() -> Vec<(&'static str, Morphology, Mesh)> {
    FILES
        .iter()
        .map(|&name| {
            let m = Morphology::from_swc(path(name)).expect("valid fixture");
            let mesh = neuromesh::mesh_morphology(&m, &Params::default()).expect("meshes");
            eprintln!(
                "{name}: {} samples, {} triangles",
                m.len(),
                mesh.faces.len()
            );
            (name, m, mesh)
        })
        .collect()
}

/// Stages 1 to 3 of `m`: the skeleton and its tubes.
fn tube_stage(m: &Morphology, params: &Params) -> (skeleton::Skeleton, tubes::Tubes) {
    let skeleton = skeleton::prepare(m, params, FIRST_REACH.sweep_cap).expect("skeleton");
    let starts = plan::plan(&skeleton, params);
    let built = tubes::build(&skeleton, &starts, params);
    (skeleton, built)
}

fn stages(c: &mut Criterion) {
    let params = Params::default();
    let files = fixtures();

    let mut g = c.benchmark_group("parse");
    for (name, m, _) in &files {
        let bytes = std::fs::read(path(name)).expect("fixture exists");
        g.throughput(Throughput::Elements(m.len() as u64));
        g.bench_with_input(BenchmarkId::from_parameter(name), &bytes, |b, bytes| {
            b.iter(|| {
                let f = neuromesh::internals::input::swc::SwcFile::parse(black_box(bytes), name)
                    .expect("valid");
                Morphology::from_file(f).expect("valid")
            })
        });
    }
    g.finish();

    let mut g = c.benchmark_group("resample");
    for (name, m, _) in &files {
        g.throughput(Throughput::Elements(m.len() as u64));
        g.bench_with_input(BenchmarkId::from_parameter(name), m, |b, m| {
            b.iter(|| {
                skeleton::prepare(black_box(m), &params, FIRST_REACH.sweep_cap).expect("skeleton")
            })
        });
    }
    g.finish();

    let mut g = c.benchmark_group("tubes");
    g.sample_size(10).measurement_time(Duration::from_secs(6));
    for (name, m, _) in &files {
        let skeleton = skeleton::prepare(m, &params, FIRST_REACH.sweep_cap).expect("skeleton");
        let starts = plan::plan(&skeleton, &params);
        g.throughput(Throughput::Elements(m.len() as u64));
        g.bench_with_input(
            BenchmarkId::from_parameter(name),
            &skeleton,
            |b, skeleton| b.iter(|| tubes::build(black_box(skeleton), &starts, &params)),
        );
    }
    g.finish();

    let mut g = c.benchmark_group("soma");
    g.sample_size(10).measurement_time(Duration::from_secs(6));
    for (name, m, mesh) in &files {
        let (_, built) = tube_stage(m, &params);
        g.throughput(Throughput::Elements(mesh.faces.len() as u64));
        g.bench_with_input(BenchmarkId::from_parameter(name), &built, |b, built| {
            b.iter_batched(|| built.clone(), build::join_somas, BatchSize::LargeInput)
        });
    }
    g.finish();

    let mut g = c.benchmark_group("splice");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for (name, m, mesh) in &files {
        let (_, built) = tube_stage(m, &params);
        let open = build::join_somas(built);
        g.throughput(Throughput::Elements(mesh.faces.len() as u64));
        g.bench_with_input(BenchmarkId::from_parameter(name), &open, |b, open| {
            b.iter_batched(
                || open.clone(),
                |o| build::splice_all(o, params.cap_rings),
                BatchSize::LargeInput,
            )
        });
    }
    g.finish();

    let mut g = c.benchmark_group("overlaps");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for (name, m, mesh) in &files {
        let (_, built) = tube_stage(m, &params);
        let spliced = build::splice_all(build::join_somas(built), params.cap_rings);
        let (spliced, owner) = spliced.surface.into_mesh_with(spliced.stats, spliced.owner);
        g.throughput(Throughput::Elements(mesh.faces.len() as u64));
        g.bench_with_input(BenchmarkId::from_parameter(name), &spliced, |b, spliced| {
            b.iter_batched(
                || (spliced.clone(), owner.clone()),
                |(mut out, owner)| {
                    overlap::resolve(&mut out, owner);
                    out
                },
                BatchSize::LargeInput,
            )
        });
    }
    g.finish();

    type Writer = fn(&mut Vec<u8>, &Mesh) -> std::io::Result<()>;
    let obj: Writer = |w, m| neuromesh::io::write_obj(w, m);
    let ply: Writer = |w, m| neuromesh::io::write_ply(w, m);
    for (group, write) in [("write_obj", obj), ("write_ply", ply)] {
        let mut g = c.benchmark_group(group);
        g.sample_size(10);
        for (name, _, mesh) in &files {
            g.throughput(Throughput::Elements(mesh.faces.len() as u64));
            g.bench_with_input(BenchmarkId::from_parameter(name), mesh, |b, mesh| {
                b.iter(|| {
                    let mut out = Vec::new();
                    write(&mut out, black_box(mesh)).expect("in memory");
                    out
                })
            });
        }
        g.finish();
    }

    let mut g = c.benchmark_group("end_to_end");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for (name, _, mesh) in &files {
        g.throughput(Throughput::Elements(mesh.faces.len() as u64));
        g.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| neuromesh::mesh_swc(path(name), &params).expect("meshes"))
        });
    }
    g.finish();
}

criterion_group!(benches, stages);
criterion_main!(benches);
