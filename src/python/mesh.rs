//! Meshes across the boundary: a core [`Mesh`] moved into numpy arrays and
//! the pure-Python `neuromesh_rs.Mesh`, and the mesh functions that borrow
//! numpy arrays back (area, volume, check, save, load).

use std::path::PathBuf;
use std::sync::Arc;

use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use super::convert::python_mesh;
use super::morphology::PyMorphology;
use super::to_py;
use crate::io;
use crate::measure::report::MeshReport;
use crate::mesh::{BuildStats, Mesh, MeshView};

/// Borrows numpy mesh arrays as a [`MeshView`] (zero-copy) and validates it.
fn view<'a>(
    vertices: &'a PyReadonlyArray2<'_, f32>,
    faces: &'a PyReadonlyArray2<'_, u32>,
    samples: Option<&'a PyReadonlyArray1<'_, u32>>,
    origin: (f64, f64, f64),
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
        origin: [origin.0, origin.1, origin.2],
    };
    view.validate().map_err(to_py)?;
    Ok(view)
}

/// Surface area of a mesh given as arrays.
#[pyfunction(name = "_mesh_area")]
pub(super) fn mesh_area_py(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f32>,
    faces: PyReadonlyArray2<'_, u32>,
) -> PyResult<f64> {
    let v = view(&vertices, &faces, None, (0.0, 0.0, 0.0))?;
    Ok(py.detach(|| v.area()))
}

/// Signed enclosed volume of a mesh given as arrays.
#[pyfunction(name = "_mesh_volume")]
pub(super) fn mesh_volume_py(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f32>,
    faces: PyReadonlyArray2<'_, u32>,
) -> PyResult<f64> {
    let v = view(&vertices, &faces, None, (0.0, 0.0, 0.0))?;
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
    let fidelity = match &r.fidelity {
        Some(fi) => {
            let m = PyDict::new(py);
            m.set_item("samples", fi.samples)?;
            m.set_item("samples_outside", fi.samples_outside)?;
            m.set_item("outside", fi.outside.clone())?;
            m.set_item("deviation_radii", fi.deviation.radii.to_vec())?;
            m.set_item("deviation", fi.deviation.units.to_vec())?;
            m.set_item("sme", fi.deviation.mean)?;
            Some(m)
        }
        None => None,
    };
    d.set_item("fidelity", fidelity)?;
    let pairs: Vec<(u32, u32)> = r.intersecting_pairs.iter().map(|p| (p[0], p[1])).collect();
    d.set_item("intersecting_pairs", pairs)?;
    d.set_item("closed", r.is_closed())?;
    d.set_item("manifold", r.is_manifold())?;
    d.set_item("outward", r.is_outward())?;
    d.set_item("sound", r.is_sound())?;
    d.set_item("faithful", r.is_faithful())?;
    d.set_item("valid", r.is_valid())?;
    Ok(d)
}

/// The quality report of a mesh given as arrays (positions relative to
/// `origin`), as a dict.
#[pyfunction(name = "_mesh_check")]
#[pyo3(signature = (vertices, faces, vertex_sample=None, morphology=None, origin=(0.0, 0.0, 0.0)))]
#[pyo3(
    text_signature = "(vertices, faces, vertex_sample=None, morphology=None, origin=(0.0, 0.0, 0.0))"
)]
pub(super) fn mesh_check_py<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArray2<'_, f32>,
    faces: PyReadonlyArray2<'_, u32>,
    vertex_sample: Option<PyReadonlyArray1<'_, u32>>,
    morphology: Option<&Bound<'_, PyMorphology>>,
    origin: (f64, f64, f64),
) -> PyResult<Bound<'py, PyDict>> {
    let v = view(&vertices, &faces, vertex_sample.as_ref(), origin)?;
    let m = morphology.map(|m| Arc::clone(m.get().inner()));
    let report = py.detach(|| v.check(m.as_deref()));
    report_dict(py, &report)
}

/// Writes a mesh given as arrays; the extension picks the format.
#[pyfunction(name = "_mesh_save")]
#[pyo3(signature = (vertices, faces, path, vertex_sample=None, origin=(0.0, 0.0, 0.0)))]
#[pyo3(text_signature = "(vertices, faces, path, vertex_sample=None, origin=(0.0, 0.0, 0.0))")]
pub(super) fn mesh_save_py(
    py: Python<'_>,
    vertices: PyReadonlyArray2<'_, f32>,
    faces: PyReadonlyArray2<'_, u32>,
    path: PathBuf,
    vertex_sample: Option<PyReadonlyArray1<'_, u32>>,
    origin: (f64, f64, f64),
) -> PyResult<()> {
    let v = view(&vertices, &faces, vertex_sample.as_ref(), origin)?;
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
pub(super) fn frame_origin_py(lo: (f64, f64, f64), hi: (f64, f64, f64)) -> (f64, f64, f64) {
    let [x, y, z] = crate::mesh::frame_origin([lo.0, lo.1, lo.2], [hi.0, hi.1, hi.2]);
    (x, y, z)
}

/// Reads an OBJ, PLY or STL file into a `neuromesh_rs.Mesh`.
#[pyfunction(name = "load_mesh")]
pub(super) fn load_mesh_py(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyAny>> {
    let mesh = py.detach(|| io::read(&path)).map_err(to_py)?;
    python_mesh(py, mesh)
}
