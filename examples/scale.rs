//! Scaling of the whole pipeline on seeded random neurons:
//! `cargo run --release --example scale -- 10000 [SEED]` writes the tree to a
//! temporary SWC file, meshes it end to end (read, mesh, in memory) on one
//! thread, and prints samples, triangles, time and the process's peak resident
//! memory. Run one size per process so the peak belongs to that size.
use std::time::Instant;

fn peak_rss_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(10_000);
    let seed: u64 = args.next().and_then(|a| a.parse().ok()).unwrap_or(1);
    let path = std::env::temp_dir().join(format!("neuromesh-random-{n}-{seed}.swc"));
    std::fs::write(
        &path,
        neuromesh::internals::input::synthetic::random_neuron_swc(n, seed),
    )
    .expect("write");
    let before = peak_rss_mb();
    let start = Instant::now();
    let mesh = neuromesh::internals::kernel::parallel::with_threads(Some(1), || {
        neuromesh::mesh_swc(&path, &neuromesh::Params::default())
    })
    .expect("pool")
    .expect("mesh");
    let secs = start.elapsed().as_secs_f64();
    // NEUROMESH_KEEP_SWC=1 keeps the tree's file (to profile it by stage).
    if std::env::var_os("NEUROMESH_KEEP_SWC").is_none() {
        let _ = std::fs::remove_file(&path);
    } else {
        eprintln!("kept {}", path.display());
    }
    println!(
        "{n} samples: {} triangles, {:.2} s, {:.2} M triangles/s, peak memory {:.0} MB (before meshing {:.0} MB)",
        mesh.faces.len(),
        secs,
        mesh.faces.len() as f64 / secs / 1e6,
        peak_rss_mb(),
        before
    );
}
