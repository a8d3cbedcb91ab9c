//! The morphology across the boundary, and meshing from Python.
//!
//! `Morphology.mesh`, `mesh_swc` and `mesh_many` take the parameters as
//! keyword arguments with their defaults and docs expanded from the table in
//! [`crate::params`], so a new parameter reaches them (and their docstrings)
//! without an edit here.

use std::path::PathBuf;
use std::sync::Arc;

use numpy::ndarray::Array2;
use numpy::{
    AllowTypeChange, IntoPyArray, PyArray1, PyArray2, PyArrayLike1, PyArrayLike2,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList};

use super::convert::{geometry_warnings, python_mesh, warn_lines};
use super::to_py;
use crate::input::morphology::Morphology;
use crate::params::{Params, with_params};

/// A neuron skeleton: samples, tree and soma (SWC ids only at the edge).
#[pyclass(frozen, name = "Morphology", module = "neuromesh_rs._native")]
pub struct PyMorphology {
    inner: Arc<Morphology>,
    ids: PyOnceLock<Py<PyArray1<i64>>>,
    types: PyOnceLock<Py<PyArray1<i32>>>,
    xyz: PyOnceLock<Py<PyArray2<f64>>>,
    radii: PyOnceLock<Py<PyArray1<f64>>>,
    parents: PyOnceLock<Py<PyArray1<i64>>>,
}

impl PyMorphology {
    fn wrap(m: Morphology) -> Self {
        PyMorphology {
            inner: Arc::new(m),
            ids: PyOnceLock::new(),
            types: PyOnceLock::new(),
            xyz: PyOnceLock::new(),
            radii: PyOnceLock::new(),
            parents: PyOnceLock::new(),
        }
    }
}

/// The largest integer an f64 holds exactly (2^53 − 1): ids and parents
/// arrive as f64, as the SWC reader reads them.
const MAX_EXACT: f64 = 9_007_199_254_740_991.0;

/// The column `name` as integers of magnitude at most `limit`, or a
/// `ValueError` naming the first value that is not one and its index.
fn integers(name: &str, values: &[f64], limit: f64) -> PyResult<Vec<i64>> {
    values
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            if v.is_finite() && v.fract() == 0.0 && v.abs() <= limit {
                Ok(v as i64)
            } else {
                let why = if !v.is_finite() || v.fract() != 0.0 {
                    "is not an integer".to_owned()
                } else {
                    format!("is out of range (±{limit:.0})")
                };
                Err(PyValueError::new_err(format!("{name}[{i}] = {v} {why}")))
            }
        })
        .collect()
}

fn read_only<'py, T, D>(a: Bound<'py, numpy::PyArray<T, D>>) -> Bound<'py, numpy::PyArray<T, D>>
where
    T: numpy::Element,
    D: numpy::ndarray::Dimension,
{
    // Shared, cached arrays must not be mutated behind the morphology's back.
    let _ = a.call_method1("setflags", (false,));
    a
}

fn xyz_array<'py>(py: Python<'py>, rows: &[[f64; 3]]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = rows.as_flattened().to_vec();
    Array2::from_shape_vec((rows.len(), 3), flat)
        .expect("rows × 3 elements by construction")
        .into_pyarray(py)
}

impl PyMorphology {
    /// The core morphology.
    pub(super) fn inner(&self) -> &Arc<Morphology> {
        &self.inner
    }
}

/// The parameters' defaults, by name (`neuromesh_rs.DEFAULTS`).
pub(super) fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    macro_rules! defaults_of {
        ([$d:ident] $( $(#[doc = $doc:literal])* $name:ident : $ty:ident = $default:tt => $const:ident, $with:ident; )*) => {
            $( $d.set_item(stringify!($name), Params::DEFAULT.$name)?; )*
        };
    }
    let d = PyDict::new(py);
    with_params!(defaults_of! { d });
    Ok(d)
}

/// The Python type of a parameter's Rust type, for docstrings.
macro_rules! python_type {
    (f64) => {
        "float"
    };
    (u32) => {
        "int"
    };
}

/// The numpy-style "Parameters" entries of the mesh parameters.
macro_rules! params_doc {
    ($( $(#[doc = $doc:literal])* $name:ident : $ty:ident = $default:tt; )*) => {
        concat!($(
            stringify!($name), " : ", python_type!($ty), ", default ", stringify!($default), "\n",
            $("   ", $doc, "\n",)*
        )*)
    };
}

/// `Morphology`'s methods (`$methods`, written out in the invocation below)
/// with `mesh`, and the functions `mesh_swc` and `mesh_many`, each taking
/// the parameters of the table as keyword arguments.
macro_rules! with_mesh_functions {
    ([$($methods:tt)*] $( $(#[doc = $doc:literal])* $name:ident : $ty:ident = $default:tt => $const:ident, $with:ident; )*) => {
        #[pymethods]
        impl PyMorphology {
            $($methods)*

            #[doc = concat!(
                "Meshes the morphology into a ``neuromesh_rs.Mesh``.\n\n",
                "Parameters\n----------\n",
                params_doc!($($(#[doc = $doc])* $name: $ty = $default;)*),
                "\nReturns\n-------\nMesh\n",
                "\nRaises\n------\nValueError\n    A parameter out of its range.\n",
            )]
            #[pyo3(signature = (*, $($name = $default),*))]
            fn mesh<'py>(&self, py: Python<'py>, $($name: $ty),*) -> PyResult<Bound<'py, PyAny>> {
                let params = Params { $($name),* };
                let m = Arc::clone(&self.inner);
                let (mesh, warnings) = py
                    .detach(move || {
                        let warnings = geometry_warnings(&m, &params);
                        crate::mesh_morphology(&m, &params).map(|mesh| (mesh, warnings))
                    })
                    .map_err(to_py)?;
                warn_lines(py, self.inner.name(), &warnings)?;
                python_mesh(py, mesh)
            }
        }

        #[doc = concat!(
            "Reads an SWC file and meshes it into a ``neuromesh_rs.Mesh``.\n\n",
            "Parameters\n----------\n",
            "path : str or os.PathLike\n    The SWC file.\n",
            params_doc!($($(#[doc = $doc])* $name: $ty = $default;)*),
            "\nReturns\n-------\nMesh\n",
            "\nRaises\n------\nSwcError\n    The file is not valid SWC (``path``, ``line`` and ``reason`` say where and why).\n",
            "OSError\n    The file cannot be read (``FileNotFoundError`` if it does not exist).\n",
            "ValueError\n    A parameter out of its range.\n",
        )]
        #[pyfunction(name = "mesh_swc")]
        #[pyo3(signature = (path, *, $($name = $default),*))]
        pub(super) fn mesh_swc_py(py: Python<'_>, path: PathBuf, $($name: $ty),*) -> PyResult<Bound<'_, PyAny>> {
            let params = Params { $($name),* };
            let (mesh, warnings) = py
                .detach(|| {
                    params.validate()?;
                    let m = Morphology::from_swc(&path)?;
                    let warnings = geometry_warnings(&m, &params);
                    crate::mesh_morphology(&m, &params).map(|mesh| (mesh, warnings))
                })
                .map_err(to_py)?;
            warn_lines(py, &path.display().to_string(), &warnings)?;
            python_mesh(py, mesh)
        }

        /// Reads the SWC file ``input``, meshes it and writes the mesh to
        /// ``output`` (the format from its extension), detached from the
        /// interpreter; returns what ``neuromesh batch`` records of a file:
        /// ``samples``, ``triangles``, ``area``, ``volume``, ``defects`` (why
        /// the mesh is not sound, empty when it is) and ``warnings`` (what
        /// meshing changed in the file's geometry). Nothing is warned: the
        /// caller reports them (``neuromesh_rs.distributed``). Runs on
        /// ``threads`` threads (1: a cluster's worker thread is one core);
        /// a panic is a ``MeshError``, and ``seconds`` gives the time taken.
        #[pyfunction(name = "_mesh_file")]
        #[pyo3(signature = (input, output, *, threads = 1, $($name = $default),*))]
        pub(super) fn mesh_file_py<'py>(
            py: Python<'py>,
            input: PathBuf,
            output: PathBuf,
            threads: usize,
            $($name: $ty),*
        ) -> PyResult<Bound<'py, PyDict>> {
            let params = Params { $($name),* };
            let outcome = py
                .detach(|| {
                    params.validate()?;
                    let format = crate::io::Format::from_path(&output)?;
                    crate::kernel::parallel::with_threads(Some(threads), || {
                        crate::batch::run_one(&input, &|input| {
                            crate::batch::mesh_file(input, &output, format, &params, false)
                        })
                    })
                })
                .map_err(to_py)?;
            let w = outcome.result.map_err(to_py)?;
            let d = PyDict::new(py);
            d.set_item("seconds", outcome.seconds)?;
            d.set_item("samples", w.samples)?;
            d.set_item("triangles", w.triangles)?;
            d.set_item("area", w.area)?;
            d.set_item("volume", w.volume)?;
            d.set_item("defects", w.defects)?;
            d.set_item("warnings", w.warnings)?;
            Ok(d)
        }

        /// Raises the error ``mesh_swc`` would for these parameters, if any.
        #[pyfunction(name = "_check_params")]
        #[pyo3(signature = (*, $($name = $default),*))]
        pub(super) fn check_params_py($($name: $ty),*) -> PyResult<()> {
            Params { $($name),* }.validate().map_err(to_py)
        }

        #[doc = concat!(
            "Meshes many SWC files in parallel, detached from the interpreter; the\n",
            "results come back in input order.\n\n",
            "Parameters\n----------\n",
            "paths : sequence of str or os.PathLike\n    The SWC files.\n",
            "threads : int, optional\n    Threads to use (default: one per core).\n",
            "return_exceptions : bool, default False\n",
            "    Give a failed file's exception in its place instead of raising it.\n",
            "progress : bool or callable, default False\n",
            "    ``True`` writes ``meshed N of M files`` to ``sys.stderr`` as files finish;\n",
            "    a callable is called with ``(done, total)`` instead.\n",
            params_doc!($($(#[doc = $doc])* $name: $ty = $default;)*),
            "\nReturns\n-------\nlist of Mesh (or of Mesh and exceptions with ``return_exceptions``)\n",
        )]
        #[pyfunction(name = "mesh_many")]
        #[pyo3(signature = (paths, *, threads=None, return_exceptions=false, progress=None, $($name = $default),*))]
        pub(super) fn mesh_many_py<'py>(
            py: Python<'py>,
            paths: &Bound<'py, PyAny>,
            threads: Option<usize>,
            return_exceptions: bool,
            progress: Option<Bound<'py, PyAny>>,
            $($name: $ty),*
        ) -> PyResult<Bound<'py, PyList>> {
            let params = Params { $($name),* };
            let progress = Progress::from_argument(progress)?;
            mesh_many(py, path_list(paths)?, threads, return_exceptions, progress, params)
        }
    };
}

with_params!(with_mesh_functions! {
    /// Reads an SWC file.
    #[staticmethod]
    fn from_swc(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let m = py.detach(|| Morphology::from_swc(&path)).map_err(to_py)?;
        Ok(Self::wrap(m))
    }

    /// Builds a morphology from columns; `parents` holds parent ids (negative for roots).
    ///
    /// Ids, types and parents may come as integers or floats, but must hold
    /// integers (an id of 1.5 or a NaN parent raises ``ValueError`` naming
    /// the argument and the index, as the SWC reader rejects them); types
    /// must fit 32 bits.
    #[staticmethod]
    fn from_arrays(
        py: Python<'_>,
        ids: PyArrayLike1<'_, f64, AllowTypeChange>,
        types: PyArrayLike1<'_, f64, AllowTypeChange>,
        xyz: PyArrayLike2<'_, f64, AllowTypeChange>,
        radii: PyArrayLike1<'_, f64, AllowTypeChange>,
        parents: PyArrayLike1<'_, f64, AllowTypeChange>,
    ) -> PyResult<Self> {
        if xyz.ndim() != 2 || xyz.shape()[1] != 3 {
            return Err(PyValueError::new_err(format!(
                "xyz must have shape (n, 3), got {:?}",
                xyz.shape()
            )));
        }
        // Skeleton arrays are small: copy them so no numpy buffer is read while detached.
        let ids = integers("ids", &ids.as_array().to_vec(), MAX_EXACT)?;
        let types: Vec<i32> = integers("types", &types.as_array().to_vec(), f64::from(i32::MAX))?
            .into_iter()
            .map(|t| t as i32)
            .collect();
        let xyz: Vec<[f64; 3]> = xyz
            .as_array()
            .rows()
            .into_iter()
            .map(|r| [r[0], r[1], r[2]])
            .collect();
        let radii = radii.as_array().to_vec();
        let parents = integers("parents", &parents.as_array().to_vec(), MAX_EXACT)?;
        let m = py
            .detach(|| Morphology::from_arrays(&ids, &types, &xyz, &radii, &parents))
            .map_err(to_py)?;
        Ok(Self::wrap(m))
    }

    /// SWC ids (int64).
    #[getter]
    fn ids<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        self.ids
            .get_or_init(py, || {
                read_only(self.inner.ids().to_vec().into_pyarray(py)).unbind()
            })
            .bind(py)
            .clone()
    }

    /// SWC type codes (int32).
    #[getter]
    fn types<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        self.types
            .get_or_init(py, || {
                read_only(self.inner.kinds().to_vec().into_pyarray(py)).unbind()
            })
            .bind(py)
            .clone()
    }

    /// Positions, shape (n, 3), float64.
    #[getter]
    fn xyz<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        self.xyz
            .get_or_init(py, || {
                read_only(xyz_array(py, self.inner.positions())).unbind()
            })
            .bind(py)
            .clone()
    }

    /// Cleaned radii (float64, all > 0).
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.radii
            .get_or_init(py, || {
                read_only(self.inner.radii().to_vec().into_pyarray(py)).unbind()
            })
            .bind(py)
            .clone()
    }

    /// Parent ids as the file links them (-1 for roots), int64.
    #[getter]
    fn parents<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        self.parents
            .get_or_init(py, || {
                let ids = self.inner.ids();
                let p: Vec<i64> = self
                    .inner
                    .file_parents()
                    .iter()
                    .map(|&p| {
                        if p == crate::input::morphology::NO_PARENT {
                            -1
                        } else {
                            ids[p as usize]
                        }
                    })
                    .collect();
                read_only(p.into_pyarray(py)).unbind()
            })
            .bind(py)
            .clone()
    }

    /// The file name, or `<arrays>`.
    #[getter]
    fn name(&self) -> String {
        self.inner.name().to_owned()
    }

    /// `"none"`, `"single point"`, `"three-point"` or `"multi-point (contour or stack)"`.
    #[getter]
    fn soma_kind(&self) -> &'static str {
        self.inner.soma_kind().name()
    }

    /// Soma centre `(x, y, z)` or None.
    #[getter]
    fn soma_center(&self) -> Option<(f64, f64, f64)> {
        self.inner.trees().iter().find_map(|t| {
            t.soma
                .as_ref()
                .map(|s| (s.center[0], s.center[1], s.center[2]))
        })
    }

    /// Soma radius (NeuroM's definition) or None.
    #[getter]
    fn soma_radius(&self) -> Option<f64> {
        self.inner
            .trees()
            .iter()
            .find_map(|t| t.soma.as_ref().map(|s| s.radius))
    }

    /// Number of connected trees.
    #[getter]
    fn n_trees(&self) -> usize {
        self.inner.trees().len()
    }

    /// Total neurite cable length.
    #[getter]
    fn cable_length(&self) -> f64 {
        self.inner.cable_length()
    }

    /// What cleaning changed, as a dict of counts.
    #[getter]
    fn cleaning<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = self.inner.cleaning();
        let d = PyDict::new(py);
        d.set_item("duplicates_merged", c.duplicates_merged)?;
        d.set_item("copies_merged", c.copies_merged)?;
        d.set_item("cycles_broken", c.cycles_broken)?;
        d.set_item("zero_radii", c.zero_radii)?;
        d.set_item("negative_radii", c.negative_radii)?;
        d.set_item("radii_from_neighbours", c.radii_from_neighbours)?;
        d.set_item("radii_from_default", c.radii_from_default)?;
        d.set_item("soma_radius_fallbacks", c.soma_radius_fallbacks)?;
        Ok(d)
    }

    /// The `neuromesh info` summary as text.
    fn summary(&self) -> String {
        crate::measure::summary::Summary::of(&self.inner).to_string()
    }

    fn __len__(&self) -> usize {
        self.inner.len()
    }

    /// Pickles as its columns, rebuilt by ``from_arrays`` (so it travels to
    /// processes and Dask workers): the copy meshes identically; its name is
    /// ``<arrays>`` and its cleaning counts start from the cleaned columns.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(
        Bound<'py, PyAny>,
        (
            Bound<'py, PyArray1<i64>>,
            Bound<'py, PyArray1<i32>>,
            Bound<'py, PyArray2<f64>>,
            Bound<'py, PyArray1<f64>>,
            Bound<'py, PyArray1<i64>>,
        ),
    )> {
        let rebuild = py.get_type::<PyMorphology>().getattr("from_arrays")?;
        Ok((
            rebuild,
            (
                self.ids(py),
                self.types(py),
                self.xyz(py),
                self.radii(py),
                self.parents(py),
            ),
        ))
    }

    fn __repr__(&self) -> String {
        format!(
            "Morphology(name={:?}, samples={}, trees={}, soma={:?})",
            self.inner.name(),
            self.inner.len(),
            self.inner.trees().len(),
            self.inner.soma_kind().name()
        )
    }
});

/// `mesh_many`'s paths: a sequence of str or path-like objects. One path
/// alone is a `TypeError` that says so (a str is a sequence of characters).
fn path_list(paths: &Bound<'_, PyAny>) -> PyResult<Vec<PathBuf>> {
    if paths.is_instance_of::<pyo3::types::PyString>() || paths.hasattr("__fspath__")? {
        return Err(pyo3::exceptions::PyTypeError::new_err(
            "mesh_many takes a sequence of paths, got a single path: pass [path], \
             or call mesh_swc for one file",
        ));
    }
    paths.extract().map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err(format!(
            "mesh_many takes a sequence of str or os.PathLike, got {}",
            paths
                .get_type()
                .name()
                .map_or_else(|_| "?".to_owned(), |n| n.to_string())
        ))
    })
}

/// `mesh_many` once its arguments are extracted.
/// How `mesh_many` reports files as they finish.
enum Progress {
    Silent,
    /// `meshed N of M files` on `sys.stderr`.
    Stderr,
    /// A Python callable, called with `(done, total)`.
    Call(Py<PyAny>),
}

impl Progress {
    fn from_argument(arg: Option<Bound<'_, PyAny>>) -> PyResult<Progress> {
        let Some(arg) = arg else {
            return Ok(Progress::Silent);
        };
        if let Ok(flag) = arg.cast::<pyo3::types::PyBool>() {
            return Ok(if flag.is_true() {
                Progress::Stderr
            } else {
                Progress::Silent
            });
        }
        if arg.is_callable() {
            return Ok(Progress::Call(arg.unbind()));
        }
        Err(pyo3::exceptions::PyTypeError::new_err(
            "progress must be True, False or a callable taking (done, total)",
        ))
    }

    /// Says that `done` of `total` files are finished (from a worker thread,
    /// attaching to the interpreter for the moment it takes).
    fn report(&self, done: usize, total: usize) {
        if matches!(self, Progress::Silent) {
            return;
        }
        Python::attach(|py| {
            let said = match self {
                Progress::Silent => Ok(()),
                Progress::Stderr => py.import("sys").and_then(|sys| {
                    let end = if done == total { "\n" } else { "" };
                    let line = format!("\rmeshed {done} of {total} files{end}");
                    sys.getattr("stderr")?
                        .call_method1("write", (line,))
                        .map(|_| ())
                }),
                Progress::Call(f) => f.call1(py, (done, total)).map(|_| ()),
            };
            // A failing progress callback must not lose the meshes: it is
            // reported as unraisable, as Python does for callbacks.
            if let Err(e) = said {
                e.write_unraisable(py, None);
            }
        });
    }
}

fn mesh_many(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    threads: Option<usize>,
    return_exceptions: bool,
    progress: Progress,
    params: Params,
) -> PyResult<Bound<'_, PyList>> {
    params.validate().map_err(to_py)?;
    let total = paths.len();
    let outcomes = py
        .detach(|| {
            crate::batch::run(
                &paths,
                threads,
                |path| {
                    let m = Morphology::from_swc(path)?;
                    let warnings = geometry_warnings(&m, &params);
                    crate::mesh_morphology(&m, &params).map(|mesh| (mesh, warnings))
                },
                |done, _| progress.report(done, total),
            )
        })
        .map_err(to_py)?;
    let list = PyList::empty(py);
    for outcome in outcomes {
        match outcome.result {
            Ok((mesh, warnings)) => {
                warn_lines(py, &outcome.input.display().to_string(), &warnings)?;
                list.append(python_mesh(py, mesh)?)?;
            }
            Err(e) if return_exceptions => list.append(to_py(e).into_value(py))?,
            Err(e) => return Err(to_py(e)),
        }
    }
    Ok(list)
}
