//! `neuromesh batch`: many files in parallel, a progress bar on a terminal, and
//! a summary at the end.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Mutex;
use std::time::Instant;

use neuromesh::{Error, Params, batch, io};

/// What one successful file gave.
struct Written {
    triangles: usize,
    /// Why the mesh is not sound ([`neuromesh::Mesh::quick_defects`]).
    defects: Vec<String>,
}

pub fn run(
    inputs: &[PathBuf],
    out_dir: &Path,
    format: &str,
    jobs: Option<usize>,
    quiet: bool,
    allow_unsound: bool,
    params: &Params,
) -> Result<ExitCode, Error> {
    params.validate()?;
    let format = io::Format::from_extension(format).ok_or_else(|| Error::InvalidParam {
        name: "format",
        reason: format!("unknown format {format:?} (obj, ply or stl)"),
    })?;
    let files = batch::expand_inputs(inputs)?;
    // An input whose output name another took keeps the reason, and fails
    // alone when its turn comes.
    let outputs: Vec<Result<PathBuf, String>> =
        batch::output_paths(&files, out_dir, format.extension())
            .into_iter()
            .map(|o| o.map_err(|e| e.to_string()))
            .collect();
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let target: std::collections::HashMap<&Path, &Result<PathBuf, String>> =
        files.iter().map(PathBuf::as_path).zip(&outputs).collect();

    let bar =
        (!quiet && std::io::stderr().is_terminal()).then(|| Mutex::new(Bar::new(files.len())));
    let start = Instant::now();
    let outcomes = batch::run(
        &files,
        jobs,
        |input| {
            let output = target[input]
                .as_ref()
                .map_err(|reason| Error::InvalidParam {
                    name: "inputs",
                    reason: reason.clone(),
                })?;
            let mesh = neuromesh::mesh_swc(input, params)?;
            io::write_as(output, &mesh, format)?;
            Ok(Written {
                triangles: mesh.faces.len(),
                defects: mesh.quick_defects(),
            })
        },
        |done, outcome| {
            // Errors are said as they happen: a batch stopped halfway has
            // still told what failed.
            let mut bar = bar
                .as_ref()
                .map(|b| b.lock().unwrap_or_else(std::sync::PoisonError::into_inner));
            let said = match &outcome.result {
                Err(e) => Some(format!("error: {e}")),
                Ok(w) if !w.defects.is_empty() => Some(format!(
                    "{}: {}: the mesh written is not sound ({})",
                    if allow_unsound { "warning" } else { "error" },
                    outcome.input.display(),
                    w.defects.join(", ")
                )),
                Ok(_) => None,
            };
            if let Some(said) = said {
                if let Some(bar) = bar.as_mut() {
                    bar.failed += usize::from(outcome.result.is_err());
                    bar.clear();
                }
                eprintln!("{said}");
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
    let wall = start.elapsed().as_secs_f64();

    let (mut failed, mut unsound) = (0, 0);
    let (mut triangles, mut busy) = (0usize, 0.0);
    for o in &outcomes {
        busy += o.seconds;
        match &o.result {
            Ok(w) => {
                triangles += w.triangles;
                unsound += usize::from(!w.defects.is_empty());
            }
            Err(_) => failed += 1,
        }
    }
    let threads = batch::thread_count(jobs)?;
    let done = outcomes.len() - failed;
    println!(
        "files      {} ({done} meshed, {failed} failed)",
        outcomes.len()
    );
    println!("output     {}/*.{}", out_dir.display(), format.extension());
    println!(
        "triangles  {triangles} ({:.2} M/s)",
        triangles as f64 / wall.max(1e-9) / 1e6
    );
    println!(
        "time       {wall:.2} s wall, {busy:.2} s summed over files, {threads} thread{}",
        if threads == 1 { "" } else { "s" }
    );
    if unsound > 0 {
        println!("unsound    {unsound} (written; reasons above)");
    }
    if failed > 0 {
        println!("failed     {failed} (reasons above)");
        return Ok(ExitCode::from(1));
    }
    if unsound > 0 && !allow_unsound {
        return Ok(ExitCode::from(4));
    }
    Ok(ExitCode::SUCCESS)
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
