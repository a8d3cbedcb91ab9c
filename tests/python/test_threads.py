"""Meshing from many threads at once: it finishes, agrees, and releases the GIL."""

from __future__ import annotations

import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

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
