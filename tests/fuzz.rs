//! The bounded fuzz run of CI: every mutation of `input::mutate` applied,
//! with fixed seeds, to the corpus's smallest files, read and meshed in
//! process. Each must give a sound mesh (the full check: closed, manifold,
//! outward, no self-intersection) or a clear error that names the file
//! (and, for bad content, the line), never a panic or an internal error.
//!
//! The face limit is lowered to 3 M triangles so that a mutant asking for
//! more is refused by the work budget, as the CLI refuses one past its
//! default: that keeps this run to about a minute. `examples/fuzz` runs the
//! same mutations through the binary, on every file, for as long as asked.

mod common;

use neuromesh::internals::input::mutate::{KINDS, mutate};
use neuromesh::internals::input::swc::SwcFile;
use neuromesh::internals::kernel::rng::Rng;
use neuromesh::{Error, Morphology, Params};

/// Files of the corpus used: the smallest, so each mesh takes little time.
const FILES: usize = 5;
/// Mutants of each kind per file.
const SEEDS: u64 = 2;

#[test]
fn mutants_of_real_files_mesh_soundly_or_fail_clearly() {
    let mut files = common::real_files();
    files.sort_by_key(|f| std::fs::metadata(f).map_or(0, |m| m.len()));
    let params = Params::default().with_face_limit(3_000_000);
    let (mut meshed, mut refused, mut runs) = (0, 0, 0);
    let mut failures: Vec<String> = Vec::new();
    for file in files.iter().take(FILES) {
        let text = String::from_utf8_lossy(&std::fs::read(file).expect("readable")).into_owned();
        for kind in 0..KINDS.len() {
            // NEUROMESH_FUZZ_KIND=name runs one mutation (when working on it).
            if std::env::var("NEUROMESH_FUZZ_KIND").is_ok_and(|k| k != KINDS[kind]) {
                continue;
            }
            for seed in 0..SEEDS {
                let mut rng = Rng::new(seed * 1000 + kind as u64);
                let Some(variant) = mutate(&text, kind, &mut rng) else {
                    continue;
                };
                runs += 1;
                let name = format!("{}~{}~{seed}", file.display(), KINDS[kind]);
                let start = std::time::Instant::now();
                let result = std::panic::catch_unwind(|| {
                    let m = Morphology::from_file(SwcFile::parse(variant.as_bytes(), &name)?)?;
                    neuromesh::mesh_morphology(&m, &params)
                });
                let seconds = start.elapsed().as_secs_f64();
                if seconds > 2.0 {
                    println!("{name}: {seconds:.1} s");
                }
                match result {
                    Err(_) => failures.push(format!("{name}: panicked")),
                    Ok(Ok(mesh)) => {
                        let report = mesh.check();
                        if report.is_sound() {
                            meshed += 1;
                        } else {
                            failures.push(format!("{name}: not sound\n{report}"));
                        }
                    }
                    Ok(Err(e @ Error::Internal(_))) => failures.push(format!("{name}: {e}")),
                    Ok(Err(e)) => {
                        let said = e.to_string();
                        if said.starts_with(&name) {
                            refused += 1;
                        } else {
                            failures.push(format!(
                                "{name}: an error that does not name the file: {said}"
                            ));
                        }
                    }
                }
            }
        }
    }
    println!("{runs} mutants: {meshed} meshed soundly, {refused} refused with a clear error");
    assert!(
        failures.is_empty(),
        "{} of {runs} mutants failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        meshed > runs / 3,
        "most mutants should still mesh: {meshed} of {runs}"
    );
}
