"""Morphology from files and from arrays, agreeing with each other and with the CLI."""

from __future__ import annotations

import json
import pickle
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import neuromesh_rs


def test_every_real_file_reads(real_files: list[Path]) -> None:
    for f in real_files:
        m = neuromesh_rs.Morphology.from_swc(f)
        assert len(m) == len(m.ids) == len(m.radii) == m.xyz.shape[0]
        assert m.xyz.dtype == np.float64 and m.ids.dtype == np.int64
        assert (m.radii > 0).all(), f.name
        assert m.n_trees >= 1


def test_arrays_round_trip(small_cell: Path) -> None:
    a = neuromesh_rs.Morphology.from_swc(small_cell)
    b = neuromesh_rs.Morphology.from_arrays(a.ids, a.types, a.xyz, a.radii, a.parents)
    assert np.array_equal(a.ids, b.ids)
    assert np.array_equal(a.parents, b.parents)
    assert np.allclose(a.xyz, b.xyz)
    assert a.soma_kind == b.soma_kind
    ma, mb = a.mesh(), b.mesh()
    assert np.array_equal(ma.vertices, mb.vertices)
    assert np.array_equal(ma.faces, mb.faces)


def test_a_morphology_pickles_and_meshes_the_same(small_cell: Path) -> None:
    a = neuromesh_rs.Morphology.from_swc(small_cell)
    b = pickle.loads(pickle.dumps(a))
    assert isinstance(b, neuromesh_rs.Morphology)
    assert np.array_equal(a.ids, b.ids) and np.array_equal(a.radii, b.radii)
    ma, mb = a.mesh(), b.mesh()
    assert np.array_equal(ma.vertices, mb.vertices)
    assert np.array_equal(ma.faces, mb.faces)


def test_changes_to_the_geometry_are_warned(tmp_path: Path) -> None:
    cell = tmp_path / "dup.swc"
    cell.write_text("1 1 0 0 0 5 -1\n2 3 10 0 0 1 1\n3 3 10 0 0 1 2\n4 3 20 0 0 0 3\n")
    with pytest.warns(UserWarning, match="1 samples at their parent's position merged") as got:
        neuromesh_rs.mesh_swc(cell)
    assert any("took the nearest valid radius" in str(w.message) for w in got)
    m = neuromesh_rs.Morphology.from_swc(cell)
    with pytest.warns(UserWarning, match="dup.swc: 1 samples"):
        m.mesh()


def test_nan_radii_from_arrays_are_filled_and_warned() -> None:
    m = neuromesh_rs.Morphology.from_arrays(
        [1, 2, 3], [1, 3, 3], [[0, 0, 0], [5, 0, 0], [10, 0, 0]], [2, float("nan"), 1], [-1, 1, 2]
    )
    assert m.radii[1] in (2.0, 1.0)  # a neighbour's, one hop away
    with pytest.warns(UserWarning, match="took the nearest valid radius"):
        m.mesh()


def test_arrays_accept_lists_and_other_dtypes() -> None:
    m = neuromesh_rs.Morphology.from_arrays(
        [1, 2, 3], [1, 3, 3], [[0, 0, 0], [5, 0, 0], [10, 0, 0]], [2, 1, 1], [-1, 1, 2]
    )
    assert m.soma_kind == "single point"
    assert m.parents.tolist() == [-1, 1, 2]


@pytest.mark.parametrize(
    ("column", "value", "message"),
    [
        ("ids", 1.5, r"ids\[1\] = 1.5 is not an integer"),
        ("parents", 1.9, r"parents\[1\] = 1.9 is not an integer"),
        ("parents", float("nan"), r"parents\[1\] = NaN is not an integer"),
        ("types", 2**40 + 3, r"types\[1\] = .* is out of range"),
        ("ids", 2.0**60, r"ids\[1\] = .* is out of range"),
    ],
)
def test_arrays_are_as_strict_as_the_reader(column: str, value: float, message: str) -> None:
    cols = {
        "ids": [1.0, 2.0],
        "types": [1.0, 3.0],
        "xyz": [[0, 0, 0], [5, 0, 0]],
        "radii": [2.0, 1.0],
        "parents": [-1.0, 1.0],
    }
    cols[column] = [cols[column][0], value]
    with pytest.raises(ValueError, match=message):
        neuromesh_rs.Morphology.from_arrays(**cols)


def test_arrays_are_read_only_and_cached(small_cell: Path) -> None:
    m = neuromesh_rs.Morphology.from_swc(small_cell)
    assert m.xyz is m.xyz
    with pytest.raises(ValueError):
        m.radii[0] = 5.0


def test_bad_arrays_name_the_row() -> None:
    with pytest.raises(neuromesh_rs.SwcError) as e:
        neuromesh_rs.Morphology.from_arrays([1, 2], [1, 3], [[0, 0, 0], [1, 0, 0]], [1, 1], [-1, 7])
    assert e.value.line == 2
    assert e.value.path == "<arrays>"
    with pytest.raises(ValueError, match=r"shape \(n, 3\)"):
        neuromesh_rs.Morphology.from_arrays([1], [1], [[0, 0]], [1], [-1])


def _cli() -> str | None:
    root = Path(__file__).resolve().parents[2]
    for candidate in (root / "target" / "debug" / "neuromesh", root / "target" / "release" / "neuromesh"):
        if candidate.exists():
            return str(candidate)
    return shutil.which("neuromesh")


@pytest.mark.skipif(_cli() is None, reason="the neuromesh binary is not built")
def test_python_and_cli_agree_on_info(real_files: list[Path]) -> None:
    cli = _cli()
    assert cli is not None
    for f in real_files[::6]:
        out = subprocess.run([cli, "info", str(f), "--json"], check=True, capture_output=True, text=True)
        info = json.loads(out.stdout)
        m = neuromesh_rs.Morphology.from_swc(f)
        assert info["samples"] == len(m)
        assert info["trees"] == m.n_trees
        assert info["cable_length"] == pytest.approx(m.cable_length)
