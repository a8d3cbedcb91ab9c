//! Python bindings (`neuromesh_rs._native`): translation only.
//!
//! Every heavy call follows the same three steps: extract the Python arguments
//! into owned Rust values (or borrowed slices of read-only numpy arrays), detach
//! from the interpreter while the core works, and build numpy arrays from the
//! result's `Vec`s without copying. Errors become typed exceptions:
//! [`SwcError`] (a `ValueError` with `path` and `line` attributes) for malformed
//! SWC, `MeshFileError` for unreadable meshes, `ValueError` for bad parameters,
//! the matching `OSError` subclass (with `filename`) for I/O and `MeshError` (a
//! `RuntimeError`) for internal failures. No panic reaches Python: the core has
//! no input-driven panics.

// The docstrings are numpy style, read by Python, not Markdown.
#![allow(rustdoc::invalid_rust_codeblocks)]

mod batch;
mod convert;
mod mesh;
mod morphology;

use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyIsADirectoryError, PyOSError, PyPermissionError,
    PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;

use crate::Error;

pyo3::create_exception!(
    neuromesh_rs,
    SwcError,
    PyValueError,
    "A malformed SWC file or array input; `path` and `line` say where."
);
pyo3::create_exception!(
    neuromesh_rs,
    MeshFileError,
    PyValueError,
    "A mesh file (OBJ, PLY, STL) that cannot be understood."
);
pyo3::create_exception!(
    neuromesh_rs,
    MeshError,
    PyRuntimeError,
    "An internal failure of the mesher: a bug; please report it with the input."
);

/// Converts a core error into the matching Python exception.
pub(crate) fn to_py(e: Error) -> PyErr {
    match e {
        Error::Swc(ref s) => Python::attach(|py| {
            let err = SwcError::new_err(e.to_string());
            let value = err.value(py);
            let _ = value.setattr("path", s.path.clone());
            let _ = value.setattr("line", s.line);
            let _ = value.setattr("reason", s.reason.clone());
            err
        }),
        Error::Io { path, source } => {
            // Rust appends " (os error N)"; Python shows errno separately.
            let text = source.to_string();
            let text = text.split(" (os error").next().unwrap_or(&text).to_owned();
            let args = (source.raw_os_error().unwrap_or(0), text, path);
            match source.kind() {
                std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(args),
                std::io::ErrorKind::PermissionDenied => PyPermissionError::new_err(args),
                std::io::ErrorKind::AlreadyExists => PyFileExistsError::new_err(args),
                std::io::ErrorKind::IsADirectory => PyIsADirectoryError::new_err(args),
                _ => PyOSError::new_err(args),
            }
        }
        e @ Error::MeshFile { .. } => MeshFileError::new_err(e.to_string()),
        e @ (Error::InvalidParam { .. } | Error::InvalidMesh(_)) => {
            PyValueError::new_err(e.to_string())
        }
        e => MeshError::new_err(e.to_string()),
    }
}

/// The extension module.
#[pymodule]
#[pyo3(name = "_native")]
mod native {
    #[pymodule_export]
    use super::batch::{expand_inputs_py, output_paths_py, run_cli_py};
    #[pymodule_export]
    use super::mesh::{
        frame_origin_py, load_mesh_py, mesh_area_py, mesh_check_py, mesh_save_py, mesh_volume_py,
    };
    #[pymodule_export]
    use super::morphology::{
        PyMorphology, check_params_py, mesh_file_py, mesh_many_py, mesh_swc_py,
    };
    #[pymodule_export]
    use super::{MeshError, MeshFileError, SwcError};

    #[pymodule_init]
    fn init(m: &pyo3::Bound<'_, pyo3::types::PyModule>) -> pyo3::PyResult<()> {
        use pyo3::prelude::*;
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        m.add("PARAM_NAMES", crate::params::PARAM_NAMES.to_vec())?;
        m.add("DEFAULTS", super::morphology::defaults(m.py())?)?;
        let formats: Vec<&str> = crate::io::Format::ALL
            .map(crate::io::Format::extension)
            .to_vec();
        m.add("FORMATS", formats)?;
        Ok(())
    }
}
