//! Many files at once: input expansion, parallel meshing that goes on past a
//! bad file, and the outcome of each file in input order.
//!
//! Each file is meshed on its own (the per-file construction is deterministic),
//! and results are collected in input order, so the output never depends on the
//! number of threads. A panic while meshing one file is caught and reported as
//! that file's [`Error::Internal`], so one pathological input cannot take the
//! rest of a batch (or a Python interpreter) down with it.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use crate::error::{Error, Result};
pub use crate::kernel::parallel::thread_count;

/// What became of one input file.
#[derive(Debug)]
pub struct Outcome<T> {
    /// The input file.
    pub input: PathBuf,
    /// The job's result (an error names the file and, for SWC errors, the line).
    pub result: Result<T>,
    /// Wall time spent on this file, in seconds.
    pub seconds: f64,
}

/// What meshing one file into another gave ([`mesh_file`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Written {
    /// Samples of the morphology (after cleaning).
    pub samples: usize,
    /// Triangles written.
    pub triangles: usize,
    /// Surface area of the mesh written.
    pub area: f64,
    /// Enclosed volume of the mesh written.
    pub volume: f64,
    /// Why the mesh is not sound ([`crate::Mesh::quick_defects`]); empty when
    /// it is.
    pub defects: Vec<String>,
    /// What meshing changed in the file's geometry ([`crate::repairs`]) and
    /// why its radii look implausible, one line each.
    pub warnings: Vec<String>,
}

/// Reads `input`, meshes it with `params` and writes the mesh to `output` as
/// `format` (whole or not at all: [`crate::io::write_as`]): one file of a
/// batch, here or on a cluster's worker. With `strict`, a file whose parent
/// links form cycles is refused instead of mended
/// ([`crate::Morphology::refuse_cycles`]).
///
/// # Errors
/// What reading ([`crate::Morphology::from_swc`]), meshing
/// ([`crate::mesh_morphology`]) or writing gives.
pub fn mesh_file(
    input: &Path,
    output: &Path,
    format: crate::io::Format,
    params: &crate::Params,
    strict: bool,
) -> Result<Written> {
    let morphology = crate::Morphology::from_swc(input)?;
    if strict {
        morphology.refuse_cycles()?;
    }
    let mut warnings: Vec<String> = morphology.radius_warning().into_iter().collect();
    warnings.extend(crate::repairs(&morphology, params));
    let mesh = crate::mesh_morphology(&morphology, params)?;
    crate::io::write_as(output, &mesh, format)?;
    Ok(Written {
        samples: morphology.len(),
        triangles: mesh.faces.len(),
        area: mesh.area(),
        volume: mesh.volume(),
        defects: mesh.quick_defects(),
        warnings,
    })
}

/// Runs `job` on every input with `threads` workers (all cores when `None`),
/// calling `progress(done, outcome)` as each file finishes (from the worker
/// threads, in completion order). Returns the outcomes in input order.
///
/// Files are the unit of parallelism: each worker meshes whole files on its own
/// one-thread pool, taking the largest remaining file first (so one big cell
/// does not start last and leave the other cores idle). Nesting the mesher's
/// own parallel loops inside a pool shared by all files made a worker wait on
/// a file stolen by another, and 2 threads ran only 1.2 times as fast as 1.
/// When there are fewer files than threads, each file gets the spare threads.
///
/// # Errors
/// Only [`Error::InvalidParam`] for `Some(0)` threads; per-file failures are in
/// the outcomes.
pub fn run<T: Send>(
    inputs: &[PathBuf],
    threads: Option<usize>,
    job: impl Fn(&Path) -> Result<T> + Sync + Send,
    progress: impl Fn(usize, &Outcome<T>) + Sync + Send,
) -> Result<Vec<Outcome<T>>> {
    let threads = crate::kernel::parallel::thread_count(threads)?;
    let workers = if cfg!(feature = "parallel") {
        threads.min(inputs.len()).max(1)
    } else {
        1
    };
    let inner = (threads / inputs.len().max(1)).max(1);
    // Largest first; ties (and unreadable files) keep input order.
    let mut order: Vec<usize> = (0..inputs.len()).collect();
    let size = |i: usize| std::fs::metadata(&inputs[i]).map_or(0, |m| m.len());
    order.sort_by_key(|&i| std::cmp::Reverse(size(i)));

    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let slots: Vec<std::sync::Mutex<Option<Outcome<T>>>> =
        inputs.iter().map(|_| std::sync::Mutex::new(None)).collect();
    let work = || {
        loop {
            let k = next.fetch_add(1, Ordering::Relaxed);
            let Some(&i) = order.get(k) else { break };
            let outcome = run_one(&inputs[i], &job);
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, &outcome);
            *slots[i]
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner) = Some(outcome);
        }
    };
    let worker = || crate::kernel::parallel::with_threads(Some(inner), work);
    if workers == 1 {
        worker()?;
    } else {
        std::thread::scope(|s| {
            let handles: Vec<_> = (0..workers).map(|_| s.spawn(worker)).collect();
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)))
                .collect::<Result<Vec<()>>>()
        })?;
    }
    Ok(slots
        .into_iter()
        .map(|s| {
            s.into_inner()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .expect("every input is taken by a worker")
        })
        .collect())
}

/// One file, with a panic turned into the file's error.
/// Runs `job` on `input`, timed, a panic caught as that file's
/// [`Error::Internal`]: one file of [`run`], or of a cluster's task.
pub fn run_one<T>(input: &Path, job: &(impl Fn(&Path) -> Result<T> + Sync)) -> Outcome<T> {
    let start = Instant::now();
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| job(input)))
        .unwrap_or_else(|panic| {
            let msg = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".to_owned());
            Err(Error::Internal(format!(
                "{}: panic while meshing: {msg}",
                input.display()
            )))
        });
    Outcome {
        input: input.to_path_buf(),
        result,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// The SWC files named by `args`, in order, without repeats: a file is taken
/// as is; a directory gives its `*.swc` and `*.swc.gz` files (any case, not recursive) sorted
/// by name; a name whose last component holds `*` or `?` is matched against
/// the files of its (literal) folder, sorted.
///
/// # Errors
/// [`Error::Io`] for a path that does not exist or a folder that cannot be
/// read, and [`Error::InvalidParam`] when a pattern or folder yields no file.
pub fn expand_inputs(args: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out: Vec<PathBuf> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    let mut push = |p: PathBuf, out: &mut Vec<PathBuf>| {
        if seen.insert(p.clone()) {
            out.push(p);
        }
    };
    for arg in args {
        let name = arg.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name.contains(['*', '?']) {
            let dir = match arg.parent() {
                Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
                _ => PathBuf::from("."),
            };
            let found: Vec<PathBuf> = list_dir(&dir)?
                .into_iter()
                .filter(|p| {
                    p.file_name()
                        .and_then(|n| n.to_str())
                        .is_some_and(|n| wildcard_match(name, n))
                })
                .collect();
            if found.is_empty() {
                return Err(no_files(arg, "matches no file"));
            }
            found.into_iter().for_each(|p| push(p, &mut out));
        } else if arg.is_dir() {
            let found: Vec<PathBuf> = list_dir(arg)?
                .into_iter()
                .filter(|p| {
                    p.file_name()
                        .and_then(|n| n.to_str())
                        .is_some_and(|n| swc_stem(n).is_some())
                })
                .collect();
            if found.is_empty() {
                return Err(no_files(arg, "holds no .swc or .swc.gz file"));
            }
            found.into_iter().for_each(|p| push(p, &mut out));
        } else if arg.exists() {
            push(arg.clone(), &mut out);
        } else {
            return Err(Error::io(
                arg,
                std::io::Error::new(std::io::ErrorKind::NotFound, "no such file or directory"),
            ));
        }
    }
    Ok(out)
}

/// Where each input's mesh goes in `out_dir`: its whole file name less a
/// final `.swc` (any case), with extension `ext`, so that
/// `H17.03.013.11.08.04.swc` gives `H17.03.013.11.08.04.ply`.
///
/// An input whose output another input earlier in the list already takes
/// (say `a/cell.swc` and `b/cell.swc`) gets an error naming both instead of a
/// path: a batch meshes the others and reports it, and never overwrites one
/// mesh with another.
pub fn output_paths(inputs: &[PathBuf], out_dir: &Path, ext: &str) -> Vec<Result<PathBuf>> {
    let mut first: std::collections::HashMap<PathBuf, &Path> = std::collections::HashMap::new();
    inputs
        .iter()
        .map(|input| {
            let out = out_dir.join(output_name(input, ext));
            if let Some(other) = first.get(&out) {
                return Err(Error::InvalidParam {
                    name: "inputs",
                    reason: format!(
                        "{} is not meshed: its output {} is already that of {}",
                        input.display(),
                        out.display(),
                        other.display(),
                    ),
                });
            }
            first.insert(out.clone(), input);
            Ok(out)
        })
        .collect()
}

/// `name` less a final `.swc` or `.swc.gz` (any case), if it has one and
/// something is left.
fn swc_stem(name: &str) -> Option<&str> {
    [".swc", ".swc.gz"].iter().find_map(|suffix| {
        let cut = name.len().checked_sub(suffix.len())?;
        (cut > 0 && name.is_char_boundary(cut) && name[cut..].eq_ignore_ascii_case(suffix))
            .then(|| &name[..cut])
    })
}

/// `input`'s file name less a final `.swc` or `.swc.gz` (any case), plus `.ext`.
fn output_name(input: &Path, ext: &str) -> std::ffi::OsString {
    let name = input.file_name().unwrap_or(input.as_os_str());
    let stem = name
        .to_str()
        .and_then(swc_stem)
        .map_or_else(|| name.to_os_string(), std::ffi::OsString::from);
    let mut out = stem;
    out.push(".");
    out.push(ext);
    out
}

fn no_files(arg: &Path, why: &str) -> Error {
    Error::InvalidParam {
        name: "inputs",
        reason: format!("{} {why}", arg.display()),
    }
}

/// The regular files of `dir`, sorted by name.
fn list_dir(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| Error::io(dir, e))?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    Ok(files)
}

/// Whether `name` matches `pattern`, where `*` stands for any run of
/// characters and `?` for one character.
pub fn wildcard_match(pattern: &str, name: &str) -> bool {
    let (p, n): (Vec<char>, Vec<char>) = (pattern.chars().collect(), name.chars().collect());
    // Greedy match with backtracking to the last star: linear in practice.
    let (mut i, mut j) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while j < n.len() {
        if i < p.len() && (p[i] == '?' || p[i] == n[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some((i, j));
            i += 1;
        } else if let Some((si, sj)) = star {
            i = si + 1;
            j = sj + 1;
            star = Some((si, sj + 1));
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == '*')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wildcards() {
        assert!(wildcard_match("*.swc", "cell.swc"));
        assert!(wildcard_match("c?ll*.swc", "cell_01.swc"));
        assert!(wildcard_match("*", ""));
        assert!(!wildcard_match("*.swc", "cell.swc.bak"));
        assert!(!wildcard_match("?", ""));
        assert!(wildcard_match("a*b*c", "aXbYbZc"));
        assert!(!wildcard_match("a*b*c", "aXbYbZ"));
    }

    #[test]
    fn outputs_keep_dotted_names_and_collisions_fail_alone() {
        let inputs = [
            PathBuf::from("a/cell.swc"),
            PathBuf::from("H17.03.013.11.08.04.swc"),
            PathBuf::from("H17.03.013.11.08.05.SWC"),
            PathBuf::from("b/cell.SWC"),
            PathBuf::from("notes.txt"),
        ];
        let out = output_paths(&inputs, Path::new("out"), "ply");
        let ok = |i: usize| out[i].as_ref().unwrap().clone();
        assert_eq!(ok(0), PathBuf::from("out/cell.ply"));
        assert_eq!(ok(1), PathBuf::from("out/H17.03.013.11.08.04.ply"));
        assert_eq!(ok(2), PathBuf::from("out/H17.03.013.11.08.05.ply"));
        assert_eq!(ok(4), PathBuf::from("out/notes.txt.ply"));
        let err = out[3].as_ref().unwrap_err().to_string();
        assert!(
            err.contains("b/cell.SWC") && err.contains("a/cell.swc"),
            "{err}"
        );
    }

    #[test]
    fn a_panicking_job_fails_alone_and_order_is_kept() {
        let inputs: Vec<PathBuf> = (0..20).map(|i| PathBuf::from(format!("{i}"))).collect();
        let out = run(
            &inputs,
            Some(2),
            |p| {
                let i: usize = p.to_str().unwrap().parse().unwrap();
                assert!(i != 7, "seven is bad");
                Ok(i * 2)
            },
            |_, _| {},
        )
        .unwrap();
        for (i, o) in out.iter().enumerate() {
            assert_eq!(o.input, inputs[i]);
            match &o.result {
                Ok(v) => assert_eq!(*v, i * 2),
                Err(e) => {
                    assert_eq!(i, 7);
                    assert!(e.to_string().contains("seven is bad"), "{e}");
                }
            }
        }
        assert!(out[7].result.is_err());
    }
}
