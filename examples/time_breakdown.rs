//! Time per pipeline stage on the given SWC files, best of 5 or $REPS (developer tool;
//! run with RAYON_NUM_THREADS=1 for one core).
use std::time::Instant;

fn main() {
    let p = neuromesh::Params::default();
    for path in std::env::args().skip(1) {
        let mut best = [f64::INFINITY; 6];
        let mut tris = 0;
        let reps: usize = std::env::var("REPS")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(5);
        for _ in 0..reps {
            let mut t = Instant::now();
            let mut lap = |k: usize, best: &mut [f64; 6]| {
                best[k] = best[k].min(t.elapsed().as_secs_f64() * 1e3);
                t = Instant::now();
            };
            let m = neuromesh::Morphology::from_swc(&path).expect("swc");
            lap(0, &mut best);
            let mut stage = neuromesh::pipeline::build_tubes(&m, &p).expect("tubes");
            lap(1, &mut best);
            neuromesh::pipeline::build_somas(&mut stage);
            lap(2, &mut best);
            neuromesh::pipeline::splice_all(&mut stage, &p);
            lap(3, &mut best);
            neuromesh::pipeline::build_fillers(&mut stage, &p);
            lap(4, &mut best);
            let mesh = neuromesh::pipeline::unite(&m, &p, stage).expect("mesh");
            lap(5, &mut best);
            tris = mesh.faces.len();
        }
        let total: f64 = best.iter().sum();
        println!(
            "{}: parse {:.1}  tubes {:.1}  somas {:.1}  splice {:.1}  fillers {:.1}  overlaps {:.1}  = {:.1} ms, {tris} tris",
            std::path::Path::new(&path)
                .file_name()
                .unwrap()
                .to_string_lossy(),
            best[0],
            best[1],
            best[2],
            best[3],
            best[4],
            best[5],
            total
        );
    }
}
