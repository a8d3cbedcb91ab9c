"""Meshing from many threads at once: it finishes, agrees, and releases the GIL."""

from __future__ import annotations

import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import neuromesh_rs


def test_concurrent_meshing_gives_identical_output(small_cell: Path) -> None:
    ref = neuromesh_rs.mesh_swc(small_cell)
    with ThreadPoolExecutor(4) as pool:
        meshes = list(pool.map(lambda _: neuromesh_rs.mesh_swc(small_cell), range(8)))
    for m in meshes:
        assert np.array_equal(m.vertices, ref.vertices)
        assert np.array_equal(m.faces, ref.faces)


def test_gil_is_released_while_meshing(real_files: list[Path]) -> None:
    # A Python thread keeps counting while a big file is meshed: only possible
    # if the mesher does not hold the GIL.
    big = max(real_files, key=lambda p: p.stat().st_size)
    ticks = 0
    stop = threading.Event()

    def count() -> None:
        nonlocal ticks
        while not stop.is_set():
            ticks += 1
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    try:
        start = time.perf_counter()
        neuromesh_rs.mesh_swc(big)
        elapsed = time.perf_counter() - start
    finally:
        stop.set()
        t.join(timeout=10)
    # At 1 ms per tick a thread holding the GIL for `elapsed` would allow ~0 ticks.
    assert ticks >= min(5, int(elapsed * 1000) // 4), (ticks, elapsed)


def test_mesh_many_keeps_order_and_matches_mesh_swc(real_files: list[Path], y_swc: Path) -> None:
    paths = [y_swc, *real_files[:3]]
    one = neuromesh_rs.mesh_many(paths, threads=1)
    two = neuromesh_rs.mesh_many(paths, threads=2)
    assert len(one) == len(two) == len(paths)
    for path, a, b in zip(paths, one, two):
        ref = neuromesh_rs.mesh_swc(path)
        for m in (a, b):
            assert isinstance(m, neuromesh_rs.Mesh)
            assert np.array_equal(m.vertices, ref.vertices)
            assert np.array_equal(m.faces, ref.faces)


def test_mesh_many_goes_past_a_bad_file(tmp_path: Path, y_swc: Path) -> None:
    bad = tmp_path / "bad.swc"
    bad.write_text("1 1 0 0 0 1 -1\n2 3 1 0 x 1 1\n")
    missing = tmp_path / "missing.swc"
    got = neuromesh_rs.mesh_many([y_swc, bad, missing, y_swc], return_exceptions=True)
    assert isinstance(got[0], neuromesh_rs.Mesh) and isinstance(got[3], neuromesh_rs.Mesh)
    assert isinstance(got[1], neuromesh_rs.SwcError)
    assert got[1].line == 2
    assert isinstance(got[2], FileNotFoundError)
    # Without return_exceptions the first failure (in input order) is raised.
    with pytest.raises(neuromesh_rs.SwcError):
        neuromesh_rs.mesh_many([y_swc, bad, missing])
    with pytest.raises(ValueError, match="threads"):
        neuromesh_rs.mesh_many([y_swc], threads=0)
    with pytest.raises(ValueError, match="min_vertices"):
        neuromesh_rs.mesh_many([y_swc], min_vertices=3)


def test_mesh_many_reports_progress_and_warns_repairs(
    tmp_path: Path, y_swc: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    seen: list[tuple[int, int]] = []
    neuromesh_rs.mesh_many([y_swc, y_swc, y_swc], threads=2, progress=lambda d, t: seen.append((d, t)))
    assert sorted(seen) == [(1, 3), (2, 3), (3, 3)]
    neuromesh_rs.mesh_many([y_swc, y_swc], progress=True)
    assert capsys.readouterr().err.endswith("meshed 2 of 2 files\n")
    with pytest.raises(TypeError, match="progress"):
        neuromesh_rs.mesh_many([y_swc], progress="yes")
    # What meshing changes in a file is warned, as mesh_swc warns it.
    zero = tmp_path / "zero.swc"
    zero.write_text("1 1 0 0 0 2 -1\n2 3 5 0 0 0 1\n3 3 10 0 0 1 2\n")
    with pytest.warns(UserWarning, match="took the nearest valid radius"):
        neuromesh_rs.mesh_many([zero])
