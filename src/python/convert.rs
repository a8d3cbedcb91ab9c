//! A core [`Mesh`] moved into numpy arrays (no copy) and wrapped into the
//! pure-Python `neuromesh_rs.Mesh`.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::MeshError;
use crate::mesh::{BuildStats, Mesh};

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
    d.set_item("samples_merged", s.samples_merged)?;
    d.set_item("radii_filled", s.radii_filled)?;
    d.set_item("soma_radii_replaced", s.soma_radii_replaced)?;
    d.set_item("cycles_broken", s.cycles_broken)?;
    d.set_item("radii_raised", s.radii_raised)?;
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

/// Issues a Python warning of `category` saying `text`.
fn warn(py: Python<'_>, category: &Bound<'_, pyo3::types::PyType>, text: String) -> PyResult<()> {
    let message = std::ffi::CString::new(text).map_err(|e| MeshError::new_err(e.to_string()))?;
    PyErr::warn(py, category, &message, 1)
}

/// Issues a `UserWarning` for each of `lines` (what meshing changed in the
/// geometry of `morphology`, or why its radii look implausible), prefixed by
/// its name: what `neuromesh mesh` prints as warnings on stderr.
pub(super) fn warn_lines(py: Python<'_>, name: &str, lines: &[String]) -> PyResult<()> {
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    for line in lines {
        warn(py, &category, format!("{name}: {line}"))?;
    }
    Ok(())
}

/// What meshing `morphology` with `params` changes in its geometry, and
/// why its radii look implausible: the lines [`warn_lines`] gives.
pub(super) fn geometry_warnings(
    morphology: &crate::Morphology,
    params: &crate::Params,
) -> Vec<String> {
    let mut lines: Vec<String> = morphology.radius_warning().into_iter().collect();
    lines.extend(crate::repairs(morphology, params));
    lines
}

/// Wraps a core mesh into the pure-Python `neuromesh_rs.Mesh` class.
///
/// A mesh that is not sound ([`Mesh::quick_defects`]) comes with a
/// `RuntimeWarning` that says why: Python users see what `neuromesh mesh`
/// exits with 4 for.
pub(super) fn python_mesh(py: Python<'_>, mesh: Mesh) -> PyResult<Bound<'_, PyAny>> {
    let defects = py.detach(|| mesh.quick_defects());
    if !defects.is_empty() {
        warn(
            py,
            &py.get_type::<pyo3::exceptions::PyRuntimeWarning>(),
            format!("the mesh is not sound: {}", defects.join(", ")),
        )?;
    }
    let parts = mesh_tuple(py, mesh)?;
    py.import("neuromesh_rs._mesh")?
        .getattr("Mesh")?
        .call_method1("_from_native", parts)
}
