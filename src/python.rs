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

use std::path::PathBuf;
use std::sync::Arc;

use numpy::ndarray::Array2;
use numpy::{
    AllowTypeChange, IntoPyArray, PyArray1, PyArray2, PyArrayLike1, PyArrayLike2, PyReadonlyArray1,
    PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::exceptions::{
    PyFileExistsError, PyFileNotFoundError, PyIsADirectoryError, PyOSError, PyPermissionError,
    PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList};

use crate::input::morphology::Morphology;
use crate::measure::report::MeshReport;
use crate::mesh::{BuildStats, Mesh, MeshView};
use crate::params::*;
use crate::{Error, io};

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
fn to_py(e: Error) -> PyErr {
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

#[pymethods]
impl PyMorphology {
    /// Reads an SWC file.
    #[staticmethod]
    fn from_swc(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let m = py.detach(|| Morphology::from_swc(&path)).map_err(to_py)?;
        Ok(Self::wrap(m))
    }

    /// Builds a morphology from columns; `parents` holds parent ids (negative for roots).
    #[staticmethod]
    fn from_arrays(
        py: Python<'_>,
        ids: PyArrayLike1<'_, i64, AllowTypeChange>,
        types: PyArrayLike1<'_, i32, AllowTypeChange>,
        xyz: PyArrayLike2<'_, f64, AllowTypeChange>,
        radii: PyArrayLike1<'_, f64, AllowTypeChange>,
        parents: PyArrayLike1<'_, i64, AllowTypeChange>,
    ) -> PyResult<Self> {
        if xyz.ndim() != 2 || xyz.shape()[1] != 3 {
            return Err(PyValueError::new_err(format!(
                "xyz must have shape (n, 3), got {:?}",
                xyz.shape()
            )));
        }
        // Skeleton arrays are small: copy them so no numpy buffer is read while detached.
        let ids = ids.as_array().to_vec();
        let types = types.as_array().to_vec();
        let xyz: Vec<[f64; 3]> = xyz
            .as_array()
            .rows()
            .into_iter()
            .map(|r| [r[0], r[1], r[2]])
            .collect();
        let radii = radii.as_array().to_vec();
        let parents = parents.as_array().to_vec();
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

    /// Meshes the morphology into a `neuromesh_rs.Mesh`.
    #[pyo3(signature = (
        *, angle_threshold=DEFAULT_ANGLE_THRESHOLD, k1=DEFAULT_K1, min_vertices=DEFAULT_MIN_VERTICES,
        max_vertices=DEFAULT_MAX_VERTICES, cap_rings=DEFAULT_CAP_RINGS, resolution=DEFAULT_RESOLUTION,
        min_radius=DEFAULT_MIN_RADIUS, scale=DEFAULT_SCALE
    ))]
    // Literal defaults for introspection and stubtest; a Python test checks
    // them against `DEFAULTS`, which comes from `Params::DEFAULT`.
    #[pyo3(
        text_signature = "($self, *, angle_threshold=10.0, k1=1, min_vertices=12, max_vertices=64, cap_rings=3, resolution=1.0, min_radius=0.0, scale=1.0)"
    )]
    fn mesh<'py>(
        &self,
        py: Python<'py>,
        angle_threshold: f64,
        k1: u32,
        min_vertices: u32,
        max_vertices: u32,
        cap_rings: u32,
        resolution: f64,
        min_radius: f64,
        scale: f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        let params = Params {
            angle_threshold,
            k1,
            min_vertices,
            max_vertices,
            cap_rings,
            resolution,
            min_radius,
            scale,
        };
        let m = Arc::clone(&self.inner);
        let mesh = py
            .detach(move || crate::mesh_morphology(&m, &params))
            .map_err(to_py)?;
        python_mesh(py, mesh)
    }

    fn __len__(&self) -> usize {
        self.inner.len()
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
}

type MeshTuple<'py> = (
    Bound<'py, PyArray2<f32>>,
    Bound<'py, PyArray2<u32>>,
    Bound<'py, PyArray1<u32>>,
    Bound<'py, PyDict>,
    (f64, f64, f64),
);

fn stats_dict<'py>(py: Python<'py>, s: &BuildStats) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("branches", s.branches)?;
    d.set_item("branches_hidden", s.branches_hidden)?;
    d.set_item("contours_skipped", s.contours_skipped)?;
    d.set_item("junctions_paper", s.junctions_paper)?;
    d.set_item("junctions_moved", s.junctions_moved)?;
    d.set_item("junctions_fallback", s.junctions_fallback)?;
    d.set_item("junctions_detached", s.junctions_detached)?;
    d.set_item("soma_trunks", s.soma_trunks)?;
    d.set_item("overlap_pairs", s.overlap_pairs)?;
    d.set_item("overlap_pairs_left", s.overlap_pairs_left)?;
    d.set_item("fillers", s.fillers)?;
    Ok(d)
}

/// Moves the mesh's buffers into numpy arrays (no copy).
fn mesh_tuple(py: Python<'_>, mesh: Mesh) -> PyResult<MeshTuple<'_>> {
    let n = mesh.vertices.len();
    let f = mesh.faces.len();
    let stats = stats_dict(py, &mesh.stats)?;
    let [ox, oy, oz] = mesh.origin;
    let vertices = Array2::from_shape_vec((n, 3), mesh.vertices.into_flattened())
        .map_err(|e| MeshError::new_err(e.to_string()))?
        .into_pyarray(py);
    let faces = Array2::from_shape_vec((f, 3), mesh.faces.into_flattened())
        .map_err(|e| MeshError::new_err(e.to_string()))?
        .into_pyarray(py);
    let samples = mesh.vertex_sample.into_pyarray(py);
    Ok((vertices, faces, samples, stats, (ox, oy, oz)))
}

/// Wraps a core mesh into the pure-Python `neuromesh_rs.Mesh` class.
fn python_mesh(py: Python<'_>, mesh: Mesh) -> PyResult<Bound<'_, PyAny>> {
    let parts = mesh_tuple(py, mesh)?;
    py.import("neuromesh_rs._mesh")?
        .getattr("Mesh")?
        .call_method1("_from_native", parts)
}

/// Reads an SWC file and meshes it into a `neuromesh_rs.Mesh`.
#[pyfunction(name = "mesh_swc")]
#[pyo3(signature = (
    path, *, angle_threshold=DEFAULT_ANGLE_THRESHOLD, k1=DEFAULT_K1, min_vertices=DEFAULT_MIN_VERTICES,
    max_vertices=DEFAULT_MAX_VERTICES, cap_rings=DEFAULT_CAP_RINGS, resolution=DEFAULT_RESOLUTION,
    min_radius=DEFAULT_MIN_RADIUS, scale=DEFAULT_SCALE
))]
#[pyo3(
    text_signature = "(path, *, angle_threshold=10.0, k1=1, min_vertices=12, max_vertices=64, cap_rings=3, resolution=1.0, min_radius=0.0, scale=1.0)"
)]
fn mesh_swc_py(
    py: Python<'_>,
    path: PathBuf,
    angle_threshold: f64,
    k1: u32,
    min_vertices: u32,
    max_vertices: u32,
    cap_rings: u32,
    resolution: f64,
    min_radius: f64,
    scale: f64,
) -> PyResult<Bound<'_, PyAny>> {
    let params = Params {
        angle_threshold,
        k1,
        min_vertices,
        max_vertices,
        cap_rings,
        resolution,
        min_radius,
        scale,
    };
    let mesh = py
        .detach(|| crate::mesh_swc(&path, &params))
        .map_err(to_py)?;
    python_mesh(py, mesh)
}

/// Meshes many SWC files in parallel, detached from the interpreter; the
/// results come back in input order, a failed file as its exception.
#[pyfunction(name = "mesh_many")]
#[pyo3(signature = (
    paths, *, threads=None, return_exceptions=false, angle_threshold=DEFAULT_ANGLE_THRESHOLD,
    k1=DEFAULT_K1, min_vertices=DEFAULT_MIN_VERTICES, max_vertices=DEFAULT_MAX_VERTICES,
    cap_rings=DEFAULT_CAP_RINGS, resolution=DEFAULT_RESOLUTION, min_radius=DEFAULT_MIN_RADIUS,
    scale=DEFAULT_SCALE
))]
#[pyo3(
    text_signature = "(paths, *, threads=None, return_exceptions=False, angle_threshold=10.0, k1=1, min_vertices=12, max_vertices=64, cap_rings=3, resolution=1.0, min_radius=0.0, scale=1.0)"
)]
fn mesh_many_py(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    threads: Option<usize>,
    return_exceptions: bool,
    angle_threshold: f64,
    k1: u32,
    min_vertices: u32,
    max_vertices: u32,
    cap_rings: u32,
    resolution: f64,
    min_radius: f64,
    scale: f64,
) -> PyResult<Bound<'_, PyList>> {
    let params = Params {
        angle_threshold,
        k1,
        min_vertices,
        max_vertices,
        cap_rings,
        resolution,
        min_radius,
        scale,
    };
    params.validate().map_err(to_py)?;
    let outcomes = py
        .detach(|| {
            crate::batch::run(
                &paths,
                threads,
                |path| crate::mesh_swc(path, &params),
                |_, _| {},
            )
        })
        .map_err(to_py)?;
    let list = PyList::empty(py);
    for outcome in outcomes {
        match outcome.result {
            Ok(mesh) => list.append(python_mesh(py, mesh)?)?,
            Err(e) if return_exceptions => list.append(to_py(e).into_value(py))?,
            Err(e) => return Err(to_py(e)),
        }
    }
    Ok(list)
}

/// Borrows numpy mesh arrays as a [`MeshView`] (zero-copy) and validates it.
fn view<'a>(
    vertices: &'a PyReadonlyArray2<'_, f32>,
    faces: &'a PyReadonlyArray2<'_, u32>,
    samples: Option<&'a PyReadonlyArray1<'_, u32>>,
) -> PyResult<MeshView<'a>> {
    let shape_err = |what: &str, shape: &[usize]| {
        PyValueError::new_err(format!("{what} must have shape (n, 3), got {shape:?}"))
    };
    if vertices.shape()[1] != 3 {
        return Err(shape_err("vertices", vertices.shape()));
    }
    if faces.shape()[1] != 3 {
        return Err(shape_err("faces", faces.shape()));
    }
    let contiguous =
        |e: numpy::AsSliceError| PyValueError::new_err(format!("arrays must be C-contiguous: {e}"));
    let (v, _) = vertices.as_slice().map_err(contiguous)?.as_chunks::<3>();
    let (f, _) = faces.as_slice().map_err(contiguous)?.as_chunks::<3>();
    let s = match samples {
        Some(s) => s.as_slice().map_err(contiguous)?,
        None => &[],
    };
    let view = MeshView {
        vertices: v,
        faces: f,
        vertex_sample: s,
    };
    view.validate().map_err(to_py)?;
    Ok(view)
}

/// Surface area of a mesh given as arrays.
#[pyfunction(name = "_mesh_area")]
fn mesh_area_py(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f32>,
    faces: PyReadonlyArray2<'_, u32>,
) -> PyResult<f64> {
    let v = view(&vertices, &faces, None)?;
    Ok(py.detach(|| v.area()))
}

/// Signed enclosed volume of a mesh given as arrays.
#[pyfunction(name = "_mesh_volume")]
fn mesh_volume_py(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f32>,
    faces: PyReadonlyArray2<'_, u32>,
) -> PyResult<f64> {
    let v = view(&vertices, &faces, None)?;
    Ok(py.detach(|| v.volume()))
}

fn report_dict<'py>(py: Python<'py>, r: &MeshReport) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("vertices", r.vertices)?;
    d.set_item("faces", r.faces)?;
    d.set_item("edges", r.edges)?;
    d.set_item("boundary_edges", r.boundary_edges)?;
    d.set_item("nonmanifold_edges", r.nonmanifold_edges)?;
    d.set_item("misoriented_edges", r.misoriented_edges)?;
    d.set_item("nonmanifold_vertices", r.nonmanifold_vertices)?;
    d.set_item("unreferenced_vertices", r.unreferenced_vertices)?;
    d.set_item("degenerate_faces", r.degenerate_faces)?;
    d.set_item("duplicate_faces", r.duplicate_faces)?;
    d.set_item("components", r.components)?;
    d.set_item("inward_components", r.inward_components)?;
    d.set_item("euler_characteristic", r.euler_characteristic)?;
    d.set_item("area", r.area)?;
    d.set_item("volume", r.volume)?;
    d.set_item("self_intersections", r.self_intersections)?;
    d.set_item("construction_intersections", r.construction_intersections)?;
    d.set_item("skeleton_overlaps", r.skeleton_overlaps)?;
    d.set_item("soma_area", r.soma_area)?;
    let skeleton = match r.skeleton {
        Some(k) => {
            let m = PyDict::new(py);
            m.set_item("soma_surface", k.soma_surface)?;
            m.set_item("total_surface", k.total_surface)?;
            m.set_item("total_volume", k.total_volume)?;
            m.set_item("union_area", k.union.map(|u| u.area))?;
            m.set_item("union_volume", k.union.map(|u| u.volume))?;
            Some(m)
        }
        None => None,
    };
    d.set_item("skeleton", skeleton)?;
    let pairs: Vec<(u32, u32)> = r.intersecting_pairs.iter().map(|p| (p[0], p[1])).collect();
    d.set_item("intersecting_pairs", pairs)?;
    d.set_item("closed", r.is_closed())?;
    d.set_item("manifold", r.is_manifold())?;
    d.set_item("outward", r.is_outward())?;
    d.set_item("valid", r.is_valid())?;
    Ok(d)
}

/// The quality report of a mesh given as arrays, as a dict.
#[pyfunction(name = "_mesh_check")]
#[pyo3(signature = (vertices, faces, vertex_sample=None, morphology=None))]
fn mesh_check_py<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'_, f32>,
    faces: PyReadonlyArray2<'_, u32>,
    vertex_sample: Option<PyReadonlyArray1<'_, u32>>,
    morphology: Option<&Bound<'_, PyMorphology>>,
) -> PyResult<Bound<'py, PyDict>> {
    let v = view(&vertices, &faces, vertex_sample.as_ref())?;
    let m = morphology.map(|m| Arc::clone(&m.get().inner));
    let report = py.detach(|| v.check(m.as_deref()));
    report_dict(py, &report)
}

/// Writes a mesh given as arrays; the extension picks the format.
#[pyfunction(name = "_mesh_save")]
#[pyo3(signature = (vertices, faces, path, vertex_sample=None, origin=(0.0, 0.0, 0.0)))]
#[pyo3(text_signature = "(vertices, faces, path, vertex_sample=None, origin=(0.0, 0.0, 0.0))")]
fn mesh_save_py(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f32>,
    faces: PyReadonlyArray2<'_, u32>,
    path: PathBuf,
    vertex_sample: Option<PyReadonlyArray1<'_, u32>>,
    origin: (f64, f64, f64),
) -> PyResult<()> {
    let v = view(&vertices, &faces, vertex_sample.as_ref())?;
    // The writers take a Mesh; building one copies the arrays once, which is
    // cheap next to formatting the file.
    let mesh = Mesh {
        vertices: v.vertices.to_vec(),
        faces: v.faces.to_vec(),
        vertex_sample: v.vertex_sample.to_vec(),
        stats: BuildStats::default(),
        origin: [origin.0, origin.1, origin.2],
    };
    py.detach(|| io::write(&path, &mesh)).map_err(to_py)
}

/// The origin a mesh spanning the box `lo`..`hi` is stored around
/// ([`crate::mesh::frame_origin`]).
#[pyfunction(name = "_frame_origin")]
fn frame_origin_py(lo: (f64, f64, f64), hi: (f64, f64, f64)) -> (f64, f64, f64) {
    let [x, y, z] = crate::mesh::frame_origin([lo.0, lo.1, lo.2], [hi.0, hi.1, hi.2]);
    (x, y, z)
}

/// Reads an OBJ, PLY or STL file into a `neuromesh_rs.Mesh`.
#[pyfunction(name = "load_mesh")]
fn load_mesh_py(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyAny>> {
    let mesh = py.detach(|| io::read(&path)).map_err(to_py)?;
    python_mesh(py, mesh)
}

/// The extension module.
#[pymodule]
#[pyo3(name = "_native")]
mod native {
    #[pymodule_export]
    use super::{
        MeshError, MeshFileError, PyMorphology, SwcError, frame_origin_py, load_mesh_py,
        mesh_area_py, mesh_check_py, mesh_many_py, mesh_save_py, mesh_swc_py, mesh_volume_py,
    };

    #[pymodule_init]
    fn init(m: &pyo3::Bound<'_, pyo3::types::PyModule>) -> pyo3::PyResult<()> {
        use pyo3::prelude::*;
        m.add("__version__", env!("CARGO_PKG_VERSION"))?;
        m.add("PARAM_NAMES", crate::params::PARAM_NAMES.to_vec())?;
        let defaults = pyo3::types::PyDict::new(m.py());
        let p = crate::params::Params::DEFAULT;
        defaults.set_item("angle_threshold", p.angle_threshold)?;
        defaults.set_item("k1", p.k1)?;
        defaults.set_item("min_vertices", p.min_vertices)?;
        defaults.set_item("max_vertices", p.max_vertices)?;
        defaults.set_item("cap_rings", p.cap_rings)?;
        defaults.set_item("resolution", p.resolution)?;
        defaults.set_item("min_radius", p.min_radius)?;
        defaults.set_item("scale", p.scale)?;
        m.add("DEFAULTS", defaults)?;
        Ok(())
    }
}
