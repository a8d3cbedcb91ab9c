"""neuromesh_rs.distributed.mesh_corpus on a LocalCluster against `neuromesh batch`.

Meshes the 48 corpus files with ``mesh_corpus`` on a LocalCluster of
``--workers`` single-thread worker processes and with ``neuromesh batch -j
WORKERS``, interleaved round by round (the machine is shared: a ratio taken
in one run is what holds), and then many copies of a tiny cell the same two
ways, which gives the scheduler's cost per file. Wall time, since both run
in parallel; the cluster is started once, before the rounds.

    python benches/dask_corpus.py --neuromesh target/ci/neuromesh

Needs the ``dask`` extra (``pip install .[dask]``) and a built CLI.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path
from statistics import median

import distributed

from neuromesh_rs.distributed import mesh_corpus

ROOT = Path(__file__).resolve().parents[1]


def run_batch(neuromesh: str, inputs: Path, out: Path, jobs: int) -> float:
    shutil.rmtree(out, ignore_errors=True)
    start = time.perf_counter()
    subprocess.run(
        [neuromesh, "batch", str(inputs), "-o", str(out), "-j", str(jobs), "--quiet"],
        check=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    return time.perf_counter() - start


def run_dask(client: distributed.Client, inputs: Path, out: Path) -> float:
    shutil.rmtree(out, ignore_errors=True)
    start = time.perf_counter()
    table = mesh_corpus(inputs, out, client=client, skip_existing=False)
    seconds = time.perf_counter() - start
    bad = table[table["status"] == "failed"]
    if len(bad):
        raise SystemExit(f"mesh_corpus failed on {len(bad)} files: {bad['error'].tolist()}")
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--neuromesh", default=str(ROOT / "target" / "ci" / "neuromesh"))
    parser.add_argument("--corpus", default=str(ROOT / "tests" / "data" / "real"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--copies", type=int, default=400, help="tiny files for the overhead")
    args = parser.parse_args()

    corpus = Path(args.corpus)
    files = sorted(corpus.glob("*.swc"))
    with tempfile.TemporaryDirectory(prefix="neuromesh-bench-") as tmp:
        tmp_path = Path(tmp)
        tiny = tmp_path / "tiny"
        tiny.mkdir()
        for k in range(args.copies):
            shutil.copy(ROOT / "tests" / "data" / "y_bifurcation.swc", tiny / f"y{k:05}.swc")

        cluster = distributed.LocalCluster(
            n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=None
        )
        client = distributed.Client(cluster)
        try:
            # One untimed pass each: page cache, worker imports.
            run_dask(client, tiny, tmp_path / "warm")
            run_batch(args.neuromesh, tiny, tmp_path / "warm", args.workers)
            times: dict[str, list[float]] = {"batch": [], "dask": [], "batch tiny": [], "dask tiny": []}
            for _ in range(args.rounds):
                times["batch"].append(run_batch(args.neuromesh, corpus, tmp_path / "b", args.workers))
                times["dask"].append(run_dask(client, corpus, tmp_path / "d"))
                times["batch tiny"].append(
                    run_batch(args.neuromesh, tiny, tmp_path / "bt", args.workers)
                )
                times["dask tiny"].append(run_dask(client, tiny, tmp_path / "dt"))
        finally:
            client.close()
            cluster.close()

    m = {k: median(v) for k, v in times.items()}
    print(
        f"machine: {os.cpu_count()} cores, load {os.getloadavg()[0]:.2f}; "
        f"{args.workers} workers; median of {args.rounds} interleaved rounds (wall)"
    )
    print(f"| run | files | batch -j {args.workers} (s) | mesh_corpus (s) | throughput ratio |")
    print("| --- | ---: | ---: | ---: | ---: |")
    print(
        f"| corpus | {len(files)} | {m['batch']:.2f} | {m['dask']:.2f} | "
        f"{m['batch'] / m['dask']:.2f} |"
    )
    print(
        f"| tiny copies | {args.copies} | {m['batch tiny']:.2f} | {m['dask tiny']:.2f} | "
        f"{m['batch tiny'] / m['dask tiny']:.2f} |"
    )
    overhead = (m["dask tiny"] - m["batch tiny"]) * args.workers / args.copies
    print(f"scheduler cost per file: {1e3 * overhead:.1f} ms of a worker's time")


if __name__ == "__main__":
    main()
