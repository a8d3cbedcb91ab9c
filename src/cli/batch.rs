//! `neuromesh batch`: many files in parallel, a progress bar on a terminal, and
//! a summary at the end ([`super::ledger`]).

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use crate::{Error, Params, batch, io};

use super::ledger::{self, Row, Status};

/// How a batch runs, as its flags say.
pub struct Options<'a> {
    pub out_dir: &'a Path,
    pub format: &'a str,
    pub jobs: Option<usize>,
    pub quiet: bool,
    pub allow_unsound: bool,
    /// Refuse files whose parent links form cycles instead of mending them.
    pub strict: bool,
    /// Leave out inputs whose output exists (a finished output is whole:
    /// each is renamed into place at once).
    pub skip_existing: bool,
    /// Where to write the per-file summary as CSV.
    pub summary: Option<PathBuf>,
}

pub fn run(inputs: &[PathBuf], opts: &Options<'_>, params: &Params) -> Result<u8, Error> {
    params.validate()?;
    let format = io::Format::from_extension(opts.format).ok_or_else(|| Error::InvalidParam {
        name: "format",
        reason: format!("unknown format {:?} (obj, ply or stl)", opts.format),
    })?;
    let out_dir = opts.out_dir;
    let files = batch::expand_inputs(inputs)?;
    // An input whose output name another took keeps the reason, and fails
    // alone when its turn comes.
    let outputs: Vec<Result<PathBuf, String>> =
        batch::output_paths(&files, out_dir, format.extension())
            .into_iter()
            .map(|o| o.map_err(|e| e.to_string()))
            .collect();
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let threads = batch::thread_count(opts.jobs)?;
    let ledger = ledger::open(
        files.len(),
        opts.summary.clone(),
        format!("{}/*.{}", out_dir.display(), format.extension()),
        threads,
    );
    let mut todo: Vec<PathBuf> = Vec::with_capacity(files.len());
    let mut place: std::collections::HashMap<&Path, (usize, &Result<PathBuf, String>)> =
        std::collections::HashMap::new();
    for (index, (input, output)) in files.iter().zip(&outputs).enumerate() {
        match output {
            Ok(out) if opts.skip_existing && out.exists() => ledger.record(Row {
                index,
                input: input.clone(),
                output: Some(out.clone()),
                status: Status::Skipped,
                triangles: 0,
                seconds: 0.0,
                message: String::new(),
            }),
            _ => {
                todo.push(input.clone());
                place.insert(input.as_path(), (index, output));
            }
        }
    }

    let bar =
        (!opts.quiet && std::io::stderr().is_terminal()).then(|| Mutex::new(Bar::new(todo.len())));
    batch::run(
        &todo,
        opts.jobs,
        |input| {
            let output = place[input]
                .1
                .as_ref()
                .map_err(|reason| Error::InvalidParam {
                    name: "inputs",
                    reason: reason.clone(),
                })?;
            batch::mesh_file(input, output, format, params, opts.strict)
        },
        |done, outcome| {
            // Said and recorded as they happen: a batch stopped halfway has
            // still told what failed.
            let input = outcome.input.display();
            let (index, output) = place[outcome.input.as_path()];
            let mut said: Vec<String> = Vec::new();
            let row = match &outcome.result {
                Err(e) => {
                    said.push(format!("error: {e}"));
                    (Status::Failed, 0, e.to_string())
                }
                Ok(w) => {
                    said.extend(w.warnings.iter().map(|x| format!("warning: {input}: {x}")));
                    if w.defects.is_empty() {
                        (Status::Meshed, w.triangles, String::new())
                    } else {
                        let why = w.defects.join(", ");
                        said.push(format!(
                            "{}: {input}: the mesh written is not sound ({why})",
                            if opts.allow_unsound {
                                "warning"
                            } else {
                                "error"
                            },
                        ));
                        (Status::Unsound, w.triangles, why)
                    }
                }
            };
            ledger.record(Row {
                index,
                input: outcome.input.clone(),
                output: output.as_ref().ok().cloned(),
                status: row.0,
                triangles: row.1,
                seconds: outcome.seconds,
                message: row.2,
            });
            let mut bar = bar
                .as_ref()
                .map(|b| b.lock().unwrap_or_else(std::sync::PoisonError::into_inner));
            if !said.is_empty() {
                if let Some(bar) = bar.as_mut() {
                    bar.failed += usize::from(outcome.result.is_err());
                    bar.clear();
                }
                eprintln!("{}", said.join("\n"));
            }
            if let Some(bar) = bar.as_mut() {
                bar.draw(done, &outcome.input);
            }
        },
    )?;
    if let Some(bar) = &bar {
        bar.lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clear();
    }
    let (failed, unsound) = ledger.finish(false);
    if failed > 0 {
        return Ok(1);
    }
    if unsound > 0 && !opts.allow_unsound {
        return Ok(4);
    }
    Ok(0)
}

/// A one-line progress bar on standard error.
struct Bar {
    total: usize,
    failed: usize,
    start: Instant,
}

impl Bar {
    fn new(total: usize) -> Bar {
        Bar {
            total,
            failed: 0,
            start: Instant::now(),
        }
    }

    fn draw(&self, done: usize, last: &Path) {
        const WIDTH: usize = 30;
        let filled = WIDTH * done / self.total.max(1);
        let name = last
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let mut err = std::io::stderr().lock();
        let _ = write!(
            err,
            "\r\x1b[2K[{}{}] {done}/{} files, {} failed, {:.1} s  {name}",
            "#".repeat(filled),
            " ".repeat(WIDTH - filled),
            self.total,
            self.failed,
            self.start.elapsed().as_secs_f64()
        );
        let _ = err.flush();
    }

    fn clear(&self) {
        let mut err = std::io::stderr().lock();
        let _ = write!(err, "\r\x1b[2K");
        let _ = err.flush();
    }
}
