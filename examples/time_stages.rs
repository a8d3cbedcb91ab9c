//! Times the tube stage against the whole build (tubes, soma, splicing) on
//! the given SWC files (developer tool).
use std::time::Instant;

fn main() {
    let p = neuromesh::Params::default();
    for path in std::env::args().skip(1) {
        let m = neuromesh::Morphology::from_swc(&path).expect("swc");
        let best = |f: &dyn Fn()| {
            (0..3)
                .map(|_| {
                    let t = Instant::now();
                    f();
                    t.elapsed().as_secs_f64()
                })
                .fold(f64::INFINITY, f64::min)
        };
        let tubes = best(&|| {
            neuromesh::pipeline::build_tubes(&m, &p).expect("tubes");
        });
        let all = best(&|| {
            neuromesh::pipeline::build(&m, &p).expect("build");
        });
        println!(
            "{path}: tubes {:.1} ms, whole build {:.1} ms, soma + splicing {:.0} %",
            tubes * 1e3,
            all * 1e3,
            100.0 * (all - tubes) / all
        );
    }
}
