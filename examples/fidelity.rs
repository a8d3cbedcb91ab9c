//! Meshes every SWC file in a folder and prints, per file, how faithful the
//! mesh is to the union of the skeleton's round cones point by point: the
//! samples left outside, the vertices' deviation in local radii (median,
//! 95th percentile, worst) and their mean distance in file units; then the
//! corpus's totals (developer tool).
//!
//! `cargo run --release --example fidelity -- [folder]` (default
//! tests/data/real). `NEUROMESH_RESOLUTION` and `NEUROMESH_MIN_VERTICES`
//! override those parameters.

use std::time::Instant;

use neuromesh::internals::measure::fidelity::fidelity;

fn main() {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "tests/data/real".to_owned());
    let files = neuromesh::batch::expand_inputs(&[dir.into()]).expect("SWC files");
    let mut params = neuromesh::Params::default();
    let var = |name: &str| std::env::var(name).ok().and_then(|v| v.parse::<f64>().ok());
    if let Some(r) = var("NEUROMESH_RESOLUTION") {
        params = params.with_resolution(r);
    }
    if let Some(m) = var("NEUROMESH_MIN_VERTICES") {
        params = params.with_min_vertices(m as u32);
    }
    println!(
        "{:<52} {:>7} {:>9} {:>8} {:>5} {:>7} {:>7} {:>7} {:>9}",
        "file", "samples", "tris", "ms", "out", "med r", "p95 r", "max r", "mean"
    );
    let (mut tris, mut faithful, mut with_out, mut p95s) = (0usize, 0, 0, Vec::new());
    let mut n = 0;
    for f in files {
        let m = match neuromesh::Morphology::from_swc(&f) {
            Ok(m) => m,
            Err(e) => {
                println!("{e}");
                continue;
            }
        };
        let t = Instant::now();
        let mesh = neuromesh::mesh_morphology(&m, &params).expect("mesh");
        let ms = t.elapsed().as_secs_f64() * 1e3;
        let fi = fidelity(&mesh.view(), &m);
        let d = fi.deviation;
        n += 1;
        tris += mesh.faces.len();
        faithful += usize::from(fi.is_faithful());
        with_out += usize::from(fi.samples_outside > 0);
        p95s.push(d.radii[1]);
        println!(
            "{:<52} {:>7} {:>9} {:>8.1} {:>5} {:>7.3} {:>7.3} {:>7.3} {:>9.4}",
            f.file_name().unwrap().to_string_lossy(),
            m.len(),
            mesh.faces.len(),
            ms,
            fi.samples_outside,
            d.radii[0],
            d.radii[1],
            d.radii[2],
            d.mean
        );
    }
    p95s.sort_by(f64::total_cmp);
    println!(
        "{n} files, {tris} triangles; {with_out} with samples outside; {faithful} faithful; \
         median 95th-percentile deviation {:.3} local radii",
        p95s.get(p95s.len() / 2).copied().unwrap_or(0.0)
    );
}
