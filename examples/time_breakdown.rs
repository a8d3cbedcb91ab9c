//! Time per pipeline stage on the given SWC files, best of 5 or $REPS
//! (developer tool; run with RAYON_NUM_THREADS=1 for one core). The stages
//! run as `build::construct` runs them, then the overlap pass and its
//! retries (`pipeline::unite`).
use std::time::Instant;

use neuromesh::internals::build::{self, FIRST_REACH, filler, plan, tubes};

const STAGES: [&str; 7] = [
    "parse", "skeleton", "tubes", "somas", "splice", "fillers", "overlaps",
];

fn main() {
    let p = neuromesh::Params::default();
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(5);
    for path in std::env::args().skip(1) {
        let mut best = [f64::INFINITY; STAGES.len()];
        let mut tris = 0;
        for _ in 0..reps {
            let mut t = Instant::now();
            let mut lap = |k: usize, best: &mut [f64; STAGES.len()]| {
                best[k] = best[k].min(t.elapsed().as_secs_f64() * 1e3);
                t = Instant::now();
            };
            let m = neuromesh::Morphology::from_swc(&path).expect("swc");
            lap(0, &mut best);
            let mut skeleton =
                neuromesh::internals::skeleton::prepare(&m, &p, FIRST_REACH.sweep_cap)
                    .expect("skeleton");
            lap(1, &mut best);
            let mut starts = plan::plan(&skeleton, &p);
            let mut built = tubes::build(&skeleton, &starts, &p);
            let segments = std::mem::take(&mut built.segments);
            let fillers = filler::select::select(
                &mut skeleton,
                &mut starts,
                segments,
                &p,
                FIRST_REACH.min_gain,
            );
            lap(2, &mut best);
            let open = build::join_somas(built);
            lap(3, &mut best);
            let spliced = build::splice_all(open, p.cap_rings);
            lap(4, &mut best);
            let construction = build::build_fillers(spliced, &fillers, &skeleton, &p);
            lap(5, &mut best);
            let mesh = neuromesh::internals::pipeline::unite(&m, &p, construction).expect("mesh");
            lap(6, &mut best);
            tris = mesh.faces.len();
        }
        let total: f64 = best.iter().sum();
        let name = std::path::Path::new(&path)
            .file_name()
            .map_or_else(|| path.clone(), |n| n.to_string_lossy().into_owned());
        let laps: Vec<String> = STAGES
            .iter()
            .zip(best)
            .map(|(s, b)| format!("{s} {b:.1}"))
            .collect();
        println!("{name}: {}  = {total:.1} ms, {tris} tris", laps.join("  "));
    }
}
