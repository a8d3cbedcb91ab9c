//! The command line for the `neuromesh` console script (`neuromesh_rs._cli`),
//! and the batch rules `neuromesh batch` follows, for
//! `neuromesh_rs.distributed`: which files a list of inputs names, and where
//! each one's mesh goes.

use std::path::PathBuf;

use pyo3::prelude::*;

use super::to_py;

/// Runs the `neuromesh` command line `args` (the program's name first),
/// detached from the interpreter, and gives its exit code
/// ([`crate::cli::main`]).
#[pyfunction(name = "_run_cli")]
pub(super) fn run_cli_py(py: Python<'_>, args: Vec<String>, handle_signals: bool) -> u8 {
    py.detach(|| crate::cli::main(args, handle_signals))
}

/// The SWC files `inputs` name, in order, without repeats: a file as is, a
/// folder's `*.swc` files, a pattern's matches (`neuromesh batch`'s rules).
#[pyfunction(name = "_expand_inputs")]
pub(super) fn expand_inputs_py(py: Python<'_>, inputs: Vec<PathBuf>) -> PyResult<Vec<String>> {
    let files = py
        .detach(|| crate::batch::expand_inputs(&inputs))
        .map_err(to_py)?;
    Ok(files.iter().map(|p| p.display().to_string()).collect())
}

/// For each input, its output path in `out_dir` with extension `ext`, or,
/// when an earlier input already takes that output, `None` and the reason.
/// Paths come back as strings, so an fsspec URL (`s3://bucket/dir`) keeps
/// its double slash (a `pathlib.Path` would fold it).
#[pyfunction(name = "_output_paths")]
pub(super) fn output_paths_py(
    inputs: Vec<PathBuf>,
    out_dir: PathBuf,
    ext: &str,
) -> Vec<(Option<String>, Option<String>)> {
    crate::batch::output_paths(&inputs, &out_dir, ext)
        .into_iter()
        .map(|r| match r {
            Ok(path) => (Some(path.display().to_string()), None),
            Err(e) => (None, Some(e.to_string())),
        })
        .collect()
}
