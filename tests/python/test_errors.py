"""Errors become the right exception, with file and line, and never a panic."""

from __future__ import annotations

from pathlib import Path

import pytest

import neuromesh_rs

CASES = [
    (b"# h\n1 1 0 0 0 1 -1\n2 3 1 0\n", 3, "expected 7 fields"),
    (b"1 1 0 0 0 1 -1\n2 3 1 0 x 1 1\n", 2, "not a number"),
    (b"1 1 0 0 0 nan -1\n", 1, "finite"),
    (b"1 1 0 0 0 1 -1\n1 3 1 0 0 1 1\n", 2, "duplicate id"),
    (b"1 1 0 0 0 1 -1\n2 3 1 0 0 1 5\n", 2, "does not exist"),
    (b"", 1, "no samples"),
    (b"1 1 0 0 0 1 -1\n\x00\x01binary", 2, "binary"),
]


@pytest.mark.parametrize(("text", "line", "reason"), CASES)
def test_malformed_swc(tmp_path: Path, text: bytes, line: int, reason: str) -> None:
    p = tmp_path / "bad.swc"
    p.write_bytes(text)
    for call in (neuromesh_rs.Morphology.from_swc, neuromesh_rs.mesh_swc):
        with pytest.raises(neuromesh_rs.SwcError) as e:
            call(p)
        assert e.value.line == line
        assert e.value.path == str(p)
        assert reason in str(e.value)
        assert str(e.value).startswith(f"{p}:{line}: ")


def test_a_parent_cycle_is_broken_and_said(tmp_path: Path) -> None:
    p = tmp_path / "cycle.swc"
    p.write_bytes(b"1 1 0 0 0 2 -1\n2 3 3 0 0 1 1\n3 3 6 0 0 1 5\n4 3 9 0 0 1 3\n5 3 9 3 0 1 4\n")
    assert neuromesh_rs.Morphology.from_swc(p).cleaning["cycles_broken"] == 1
    with pytest.warns(UserWarning, match="1 cycles of parent links broken"):
        mesh = neuromesh_rs.mesh_swc(p)
    assert mesh.stats["cycles_broken"] == 1


def test_missing_file_is_file_not_found(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError) as e:
        neuromesh_rs.mesh_swc(tmp_path / "nope.swc")
    assert e.value.filename == str(tmp_path / "nope.swc")


def test_bad_parameter_is_value_error(y_swc: Path) -> None:
    with pytest.raises(ValueError, match="min_vertices"):
        neuromesh_rs.mesh_swc(y_swc, min_vertices=3)
    with pytest.raises(ValueError, match="resolution"):
        neuromesh_rs.mesh_swc(y_swc, resolution=-1.0)
    with pytest.raises(TypeError):
        neuromesh_rs.mesh_swc(y_swc, no_such_parameter=1)  # type: ignore[call-arg]


def test_unreadable_mesh_file(tmp_path: Path) -> None:
    p = tmp_path / "bad.stl"
    p.write_bytes(b"hello")
    with pytest.raises(neuromesh_rs.MeshFileError, match="not an STL file"):
        neuromesh_rs.load_mesh(p)
    with pytest.raises(ValueError, match=r"\.obj, \.ply or \.stl"):
        neuromesh_rs.load_mesh(tmp_path / "mesh.xyz")


def test_unwritable_output(tmp_path: Path, y_swc: Path) -> None:
    m = neuromesh_rs.mesh_swc(y_swc)
    with pytest.raises(OSError):
        m.save(tmp_path / "no" / "such" / "dir" / "m.obj")
