"""Mesh arrays, measures, checks, files and trimesh."""

from __future__ import annotations

import pickle
from pathlib import Path

import numpy as np
import pytest

import neuromesh_rs


def box(faults: str = "") -> neuromesh_rs.Mesh:
    v = np.array([[(i & 1), (i >> 1) & 1, (i >> 2) & 1] for i in range(8)], dtype=np.float32)
    f = [[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
         [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]]
    if "removed" in faults:
        f = f[:-1]
    if "flipped" in faults:
        f[3] = [f[3][0], f[3][2], f[3][1]]
    if "overlap" in faults:
        v = np.vstack([v, v + 0.5])
        f = f + [[a + 8, b + 8, c + 8] for a, b, c in f]
    return neuromesh_rs.Mesh(v, np.array(f))


def test_box_reports_exactly_its_faults() -> None:
    r = box().check()
    assert r.valid and r.closed and r.manifold and r.outward
    assert r.self_intersections == 0 and r.euler_characteristic == 2
    r = box("removed").check()
    assert not r.closed and r.boundary_edges == 3 and r.misoriented_edges == 0
    r = box("flipped").check()
    assert r.closed and r.misoriented_edges == 3 and not r.outward
    r = box("overlap").check()
    assert r.closed and r.manifold and r.outward and r.components == 2 and r.self_intersections > 0


def test_dtypes_shapes_and_read_only(y_swc: Path) -> None:
    m = neuromesh_rs.mesh_swc(y_swc)
    assert m.vertices.dtype == np.float32 and m.vertices.shape[1] == 3
    assert m.faces.dtype == np.uint32 and m.faces.shape[1] == 3
    assert m.vertex_sample is not None and m.vertex_sample.shape == (len(m.vertices),)
    with pytest.raises(ValueError):
        m.vertices[0, 0] = 1.0
    assert m.area > 0 and m.volume > 0


def test_mesh_labels_index_the_morphology(y_swc: Path) -> None:
    morph = neuromesh_rs.Morphology.from_swc(y_swc)
    m = morph.mesh()
    assert m.vertex_sample is not None
    assert int(m.vertex_sample.max()) < len(morph)
    # Each vertex lies within its sample's reach: a radius (with the polygon
    # correction) plus half of the longest segment, since resampled points take
    # the label of the nearest original sample.
    seg = [np.linalg.norm(morph.xyz[i] - morph.xyz[list(morph.ids).index(p)])
           for i, p in enumerate(morph.parents) if p >= 0]
    d = np.linalg.norm(m.vertices - morph.xyz[m.vertex_sample], axis=1)
    reach = 1.1 * morph.radii.max() + 0.5 * max(seg)
    assert (d <= reach).all()


def test_save_and_load_every_format(tmp_path: Path, y_swc: Path) -> None:
    m = neuromesh_rs.mesh_swc(y_swc)
    for ext in ("obj", "ply", "stl"):
        p = tmp_path / f"y.{ext}"
        m.save(p)
        back = neuromesh_rs.load_mesh(p)
        assert len(back.faces) == len(m.faces), ext
        assert back.volume == pytest.approx(m.volume, rel=1e-6), ext
    back = neuromesh_rs.load_mesh(tmp_path / "y.ply")
    assert back.vertex_sample is not None
    assert np.array_equal(back.vertex_sample, m.vertex_sample)


def test_pickle_round_trip(y_swc: Path) -> None:
    m = neuromesh_rs.mesh_swc(y_swc)
    back = pickle.loads(pickle.dumps(m))
    assert np.array_equal(back.vertices, m.vertices)
    assert back.stats == m.stats


def test_constructor_validates() -> None:
    with pytest.raises(ValueError, match="shape"):
        neuromesh_rs.Mesh(np.zeros((3, 2)), np.zeros((1, 3), dtype=np.uint32))
    with pytest.raises(ValueError, match="refer to vertex"):
        neuromesh_rs.Mesh(np.zeros((3, 3)), [[0, 1, 5]])
    with pytest.raises(ValueError, match="non-negative"):
        neuromesh_rs.Mesh(np.zeros((3, 3)), [[0, 1, -1]])


def test_to_trimesh(y_swc: Path) -> None:
    trimesh = pytest.importorskip("trimesh")
    m = neuromesh_rs.mesh_swc(y_swc)
    t = m.to_trimesh()
    assert isinstance(t, trimesh.Trimesh)
    assert len(t.faces) == len(m.faces)
    assert np.array_equal(t.vertex_attributes["sample"], m.vertex_sample)
    assert "type" not in t.vertex_attributes
    morphology = neuromesh_rs.Morphology.from_swc(y_swc)
    typed = m.to_trimesh(morphology)
    assert np.array_equal(typed.vertex_attributes["type"], morphology.types[m.vertex_sample])
    assert set(np.unique(typed.vertex_attributes["type"])) <= set(morphology.types)
    bare = neuromesh_rs.Mesh(m.vertices, m.faces)
    assert "sample" not in bare.to_trimesh().vertex_attributes
    with pytest.raises(ValueError, match="no sample labels"):
        bare.to_trimesh(morphology)


def test_a_cell_far_from_the_origin_keeps_its_precision(small_cell: Path, tmp_path: Path) -> None:
    near = neuromesh_rs.Morphology.from_swc(small_cell)
    shift = np.array([12345.678, -23456.789, 5432.1])
    far = neuromesh_rs.Morphology.from_arrays(near.ids, near.types, near.xyz + shift, near.radii, near.parents)
    a, b = near.mesh(), far.mesh()
    assert a.origin == (0.0, 0.0, 0.0) and a.vertices.dtype == np.float32
    assert b.origin != (0.0, 0.0, 0.0)
    assert b.vertices.dtype == np.float64 and b.local_vertices.dtype == np.float32
    rb, ra = b.check(far), a.check(near)
    assert rb.sound
    # The far mesh is as faithful as the near one: the origin is added back.
    assert rb.fidelity is not None and ra.fidelity is not None
    assert rb.fidelity["samples_outside"] == ra.fidelity["samples_outside"]
    assert abs(rb.fidelity["deviation_radii"][1] - ra.fidelity["deviation_radii"][1]) < 1e-3
    assert abs(b.area / a.area - 1) < 1e-3 and abs(b.volume / a.volume - 1) < 1e-3
    np.testing.assert_allclose(b.vertices.min(axis=0), a.vertices.min(axis=0) + shift, atol=1e-3)
    for ext in ("obj", "ply"):
        b.save(tmp_path / f"far.{ext}")
        back = neuromesh_rs.load_mesh(tmp_path / f"far.{ext}")
        assert back.origin != (0.0, 0.0, 0.0) and back.check().valid
        np.testing.assert_allclose(np.sort(back.vertices, axis=0), np.sort(b.vertices, axis=0), atol=1e-6)
    with pytest.warns(UserWarning, match="STL stores float32"):
        b.save(tmp_path / "far.stl")
    # Arrays given in float64 far away are stored around their centre too.
    wrapped = neuromesh_rs.Mesh(b.vertices, b.faces)
    assert wrapped.origin != (0.0, 0.0, 0.0) and wrapped.check().valid
    assert pickle.loads(pickle.dumps(b)).origin == b.origin


def test_split_by_type_covers_the_mesh_with_open_pieces(small_cell: Path, y_swc: Path) -> None:
    morphology = neuromesh_rs.Morphology.from_swc(small_cell)
    mesh = morphology.mesh()
    pieces = mesh.split_by_type(morphology)
    assert set(pieces) == set(np.unique(morphology.types))
    assert sum(len(p.faces) for p in pieces.values()) == len(mesh.faces)
    assert sum(p.area for p in pieces.values()) == pytest.approx(mesh.area, rel=1e-6)
    for t, piece in pieces.items():
        labels = morphology.types[piece.vertex_sample]
        assert np.mean(labels == t) > 0.5
    # Soma and dendrites meet: both pieces are open along the seam.
    assert all(not p.check().closed for p in pieces.values())
    # One type only: one piece, the whole closed mesh.
    y = neuromesh_rs.Morphology.from_swc(y_swc)
    whole = y.mesh()
    (only,) = whole.split_by_type(y).values()
    assert len(only.faces) == len(whole.faces) and only.check().closed
    with pytest.raises(ValueError, match="no sample labels"):
        neuromesh_rs.Mesh(whole.vertices, whole.faces).split_by_type(y)
