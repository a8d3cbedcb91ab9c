#!/usr/bin/env python3
"""Side by side: neuromesh_rs against the tools users pick today (run by hand).

On the same SWC files, in the same run, each tool is timed end to end from the
file on disk to a mesh in memory, over several repetitions (median reported):

* ``neuromesh_rs.mesh_swc`` (closed, manifold, with soma);
* navis ``tree2meshneuron`` (open, overlapping tubes, no soma);
* a manifold3d boolean union of the skeleton's round cones (each segment the
  hull of its two end spheres, soma as a sphere), the CSG approach other tools
  use for watertight meshes.

Every result is then checked with ``neuromesh_rs.Mesh(v, f).check()`` (closed:
every edge in two faces; manifold: no edge in more than two faces, no pinched
vertex). The peers are installed only in the benchmark's own environment::

    python3 -m venv .venv-peers
    .venv-peers/bin/pip install navis manifold3d .
    .venv-peers/bin/python benches/compare_peers.py            # default files
    .venv-peers/bin/python benches/compare_peers.py a.swc b.swc --repeat 7

The boolean union is slow (minutes on big cells); ``--union-max-segments``
skips it above a size and says so in the table.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_FILES = [
    ROOT / "tests/data/real" / name
    for name in (
        "rat_dentate_granule_1220882a.CNG.swc",
        "rat_CA1_CCK_interneuron_cck7632.CNG.swc",
        "mouse_V1_Scnn1a_allen_177300.swc",
        "purkinje_martone_alxP.CNG.swc",
    )
]


def read_columns(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """ids, types, xyz, radii, parent ids of an SWC file (comments skipped)."""
    rows = []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            line = line.split("#", 1)[0].strip()
            if line:
                rows.append(line.split()[:7])
    a = np.array(rows, dtype=float)
    return a[:, 0].astype(int), a[:, 1].astype(int), a[:, 2:5], a[:, 5], a[:, 6].astype(int)


def neuromesh_tool(path: Path) -> tuple[np.ndarray, np.ndarray]:
    import neuromesh_rs

    m = neuromesh_rs.mesh_swc(path)
    return m.vertices, m.faces


def navis_tool(path: Path) -> tuple[np.ndarray, np.ndarray]:
    import navis

    n = navis.read_swc(str(path))
    mesh = navis.conversion.tree2meshneuron(n)
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def union_tool(path: Path, segments: int = 12) -> tuple[np.ndarray, np.ndarray]:
    from manifold3d import Manifold, OpType

    ids, types, xyz, radii, parents = read_columns(path)
    radii = np.maximum(radii, 1e-3)
    row = {int(i): k for k, i in enumerate(ids)}
    parts = []
    sphere = Manifold.sphere(1.0, segments)

    def ball(k: int) -> Any:
        return sphere.scale([radii[k]] * 3).translate(xyz[k].tolist())

    for k, p in enumerate(parents):
        if p < 0 or int(p) not in row:
            parts.append(ball(k))
            continue
        j = row[int(p)]
        if types[k] == 1 and types[j] == 1:
            continue  # soma-internal segments: the soma is its samples' spheres
        parts.append(Manifold.batch_hull([ball(k), ball(j)]))
    for k in np.flatnonzero(types == 1):
        parts.append(ball(int(k)))
    union = Manifold.batch_boolean(parts, OpType.Add)
    mesh = union.to_mesh()
    return np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts)


def segments_of(path: Path) -> int:
    return len(read_columns(path)[0])


def time_tool(fn: Callable[[Path], tuple[np.ndarray, np.ndarray]], path: Path, repeat: int) -> tuple[float, Any]:
    times = []
    result = None
    for _ in range(repeat):
        t = time.perf_counter()
        result = fn(path)
        times.append(time.perf_counter() - t)
    return statistics.median(times), result


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="*", type=Path, default=DEFAULT_FILES)
    ap.add_argument("--repeat", type=int, default=5, help="repetitions per tool and file (median reported)")
    ap.add_argument("--union-repeat", type=int, default=1, help="repetitions of the slow boolean union")
    ap.add_argument("--union-max-segments", type=int, default=5000, help="skip the union above this many samples")
    ap.add_argument("--threads", type=int, default=1, help="neuromesh_rs threads (RAYON_NUM_THREADS); 1 is fair to the single-threaded peers")
    args = ap.parse_args()
    os.environ["RAYON_NUM_THREADS"] = str(args.threads)

    import neuromesh_rs

    tools: list[tuple[str, Callable[[Path], tuple[np.ndarray, np.ndarray]]]] = [("neuromesh_rs", neuromesh_tool)]
    try:
        import navis  # noqa: F401

        navis.set_loggers("ERROR")
        tools.append(("navis tree2meshneuron", navis_tool))
    except ImportError:
        print("navis not installed: skipped", file=sys.stderr)
    try:
        import manifold3d  # noqa: F401

        tools.append(("manifold3d union", union_tool))
    except ImportError:
        print("manifold3d not installed: skipped", file=sys.stderr)

    print(f"{'file':45} {'tool':24} {'median s':>10} {'x ours':>9} {'triangles':>10} {'closed':>6} {'manifold':>8}")
    for path in args.files:
        base = None
        for name, fn in tools:
            repeat = args.repeat
            if name == "manifold3d union":
                if segments_of(path) > args.union_max_segments:
                    print(f"{path.name[:45]:45} {name:24} {'skipped (> --union-max-segments)':>40}")
                    continue
                repeat = args.union_repeat
            t, (v, f) = time_tool(fn, path, repeat)
            if base is None:
                base = t
            report = neuromesh_rs.Mesh(np.asarray(v, dtype=np.float32), np.asarray(f, dtype=np.int64)).check()
            print(
                f"{path.name[:45]:45} {name:24} {t:10.4f} {t / base:9.1f} {len(f):10d} "
                f"{'yes' if report.closed else 'no':>6} {'yes' if report.manifold else 'no':>8}",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
