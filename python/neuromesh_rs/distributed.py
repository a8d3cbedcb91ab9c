"""Meshing an archive on a Dask cluster.

``mesh_corpus`` meshes many SWC files on the workers of a Dask
``distributed`` cluster (a ``LocalCluster`` on this machine when none is
given) and returns one row per input. Each task reads its own input and
writes its own output, so no mesh travels through the scheduler; the
meshing runs in Rust with the GIL released. A file that fails becomes a row
with its error, never a failed run, and a second call with
``skip_existing=True`` meshes only what is missing. The same from the shell::

    python -m neuromesh_rs.distributed cells/ -o meshes/ --summary result.csv

Inputs and outputs may be local paths or fsspec URLs (``s3://``, ``gs://``,
...; the matching fsspec filesystem must be installed on every worker).
Install with ``pip install neuromesh_rs[dask]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any

from . import _native

if TYPE_CHECKING:
    import pandas

__all__ = ["COLUMNS", "main", "mesh_corpus"]

#: The result table's columns, in order.
COLUMNS = (
    "input",
    "output",
    "status",
    "samples",
    "triangles",
    "area",
    "volume",
    "seconds",
    "warnings",
    "error",
)

_GLOB = set("*?[")


def _is_url(path: str) -> bool:
    """Whether ``path`` names a file through an fsspec protocol other than the local one."""
    head, sep, _ = path.partition("://")
    return bool(sep) and head.isidentifier() and head != "file"


def _local(path: str) -> str:
    """``path`` without a ``file://`` prefix."""
    return path[len("file://") :] if path.startswith("file://") else path


def _expand(inputs: str | os.PathLike[str] | Iterable[str | os.PathLike[str]]) -> list[str]:
    """The SWC files ``inputs`` name: local ones by ``neuromesh batch``'s rules
    (a file, a folder's ``*.swc`` files, a pattern's matches), URLs through
    fsspec by the same rules."""
    if isinstance(inputs, (str, os.PathLike)):
        items = [os.fspath(inputs)]
    else:
        items = [os.fspath(p) for p in inputs]
    if not items:
        raise ValueError("inputs: no input given")
    out: list[str] = []
    seen: set[str] = set()
    for item in items:
        if _is_url(item):
            found = _expand_url(item)
        else:
            found = [str(p) for p in _native._expand_inputs([_local(item)])]
        for path in found:
            if path not in seen:
                seen.add(path)
                out.append(path)
    return out


def _expand_url(url: str) -> list[str]:
    import fsspec

    fs, path = fsspec.core.url_to_fs(url)
    if _GLOB & set(path.rsplit("/", 1)[-1]):
        found = sorted(fs.glob(path))
    elif fs.isdir(path):
        found = sorted(
            p for p in fs.ls(path, detail=False) if p.lower().endswith((".swc", ".swc.gz"))
        )
    elif fs.exists(path):
        found = [path]
    else:
        raise FileNotFoundError(f"inputs: {url} does not exist")
    if not found:
        raise ValueError(f"inputs: {url} names no SWC file")
    return [fs.unstrip_protocol(p) for p in found]


def _existing(out: str) -> set[str]:
    """The file names already in the output folder ``out``."""
    if _is_url(out):
        import fsspec

        fs, path = fsspec.core.url_to_fs(out)
        if not fs.exists(path):
            return set()
        return {p.rstrip("/").rsplit("/", 1)[-1] for p in fs.ls(path, detail=False)}
    path = _local(out)
    return set(os.listdir(path)) if os.path.isdir(path) else set()


class _Failed(Exception):
    """A failure whose message is already what the row says."""


def _row(input: str, output: str | None, status: str, **fields: Any) -> dict[str, Any]:
    row: dict[str, Any] = {
        "input": input,
        "output": output,
        "status": status,
        "samples": None,
        "triangles": None,
        "area": None,
        "volume": None,
        "seconds": None,
        "warnings": "",
        "error": "",
    }
    row.update(fields)
    return row


def _mesh_task(input: str, output: str, params: dict[str, Any]) -> dict[str, Any]:
    """One file, on a worker: read, mesh, write; any failure becomes the row's error.

    Local files are read and written in place (the write is whole or not at
    all); a URL is copied through a temporary folder with fsspec, and its
    name replaces the temporary path in messages.
    """
    start = time.perf_counter()
    try:
        if not _is_url(input) and not _is_url(output):
            written = _native._mesh_file(_local(input), _local(output), **params)
        else:
            written = _mesh_through_temp(input, output, params)
    except Exception as e:  # one bad file never fails the run
        return _row(
            input,
            output,
            "failed",
            seconds=time.perf_counter() - start,
            error=str(e) if isinstance(e, _Failed) else f"{type(e).__name__}: {e}",
        )
    defects = written["defects"]
    return _row(
        input,
        output,
        "unsound" if defects else "meshed",
        samples=written["samples"],
        triangles=written["triangles"],
        area=written["area"],
        volume=written["volume"],
        seconds=time.perf_counter() - start,
        warnings="; ".join(written["warnings"]),
        error=("the mesh written is not sound: " + ", ".join(defects)) if defects else "",
    )


def _mesh_through_temp(input: str, output: str, params: dict[str, Any]) -> dict[str, Any]:
    import fsspec

    with tempfile.TemporaryDirectory(prefix="neuromesh-") as tmp:
        local_in = _local(input)
        if _is_url(input):
            local_in = os.path.join(tmp, "in", input.rstrip("/").rsplit("/", 1)[-1])
            os.makedirs(os.path.dirname(local_in))
            fs, path = fsspec.core.url_to_fs(input)
            fs.get_file(path, local_in)
        local_out = _local(output)
        if _is_url(output):
            local_out = os.path.join(tmp, output.rstrip("/").rsplit("/", 1)[-1])
        try:
            written = _native._mesh_file(local_in, local_out, **params)
        except Exception as e:
            # Name the file the user gave, not its temporary copy.
            text = str(e).replace(local_in, input).replace(local_out, output)
            raise _Failed(f"{type(e).__name__}: {text}") from e
        if _is_url(output):
            fs, path = fsspec.core.url_to_fs(output)
            fs.put_file(local_out, path)
        return written


def mesh_corpus(
    inputs: str | os.PathLike[str] | Iterable[str | os.PathLike[str]],
    out: str | os.PathLike[str],
    *,
    client: Any = None,
    format: str = "ply",
    skip_existing: bool = True,
    progress: bool = False,
    **params: Any,
) -> pandas.DataFrame:
    """Meshes every SWC file ``inputs`` names into ``out`` on a Dask cluster.

    Parameters
    ----------
    inputs : path, URL, or iterable of them
        SWC files, folders (their ``*.swc`` files) and patterns (``*``, ``?``
        in the last component), local or fsspec URLs.
    out : path or URL
        The folder the meshes go to (created if missing), named as
        ``neuromesh batch`` names them: the input's file name less ``.swc``,
        plus ``.{format}``.
    client : distributed.Client, optional
        The cluster to run on. Without one, a ``LocalCluster`` with one
        single-thread worker per core is started and closed afterwards.
    format : {"ply", "obj", "stl"}
        The mesh format.
    skip_existing : bool, default True
        Leave out inputs whose output exists (an output is written whole or
        not at all, so an existing one is finished).
    progress : bool, default False
        Show Dask's progress bar while the files are meshed (the dashboard
        shows the tasks too).
    **params
        Meshing parameters, as for ``neuromesh_rs.mesh_swc`` (see
        ``neuromesh_rs.PARAM_NAMES``).

    Returns
    -------
    pandas.DataFrame
        One row per input, in input order, with the columns ``COLUMNS``:
        ``status`` is ``meshed``, ``unsound`` (written, but the mesh is not
        sound: ``error`` says why), ``skipped`` or ``failed`` (``error``
        holds the exception's type and message); ``warnings`` says what
        meshing changed in the file's geometry; ``seconds`` is the time the
        task took on its worker.

    Raises
    ------
    TypeError
        A parameter name ``mesh_swc`` does not take.
    ValueError
        A parameter value out of range, an unknown format, or inputs that
        name no file.
    FileNotFoundError
        An input path that does not exist.
    """
    import pandas

    unknown = sorted(set(params) - set(_native.PARAM_NAMES))
    if unknown:
        raise TypeError(
            f"mesh_corpus() got unknown parameter(s) {', '.join(unknown)}; "
            f"the parameters are {', '.join(_native.PARAM_NAMES)}"
        )
    _native._check_params(**params)
    fmt = str(format).lower().lstrip(".")
    if fmt not in _native.FORMATS:
        raise ValueError(f"format: {format!r} is not one of {', '.join(_native.FORMATS)}")

    files = _expand(inputs)
    out = os.fspath(out)
    targets = _native._output_paths(files, out, fmt)
    existing = _existing(out) if skip_existing else set()
    rows: list[dict[str, Any] | None] = [None] * len(files)
    todo: list[int] = []
    for i, (path, (output, clash)) in enumerate(zip(files, targets)):
        target = None if output is None else str(output)
        if target is None:
            rows[i] = _row(path, None, "failed", error=f"ValueError: {clash}")
        elif os.path.basename(target) in existing:
            rows[i] = _row(path, target, "skipped")
        else:
            todo.append(i)
    if todo:
        # Largest first, as `neuromesh batch` does: a big cell started last
        # would leave the other workers idle at the end.
        todo.sort(key=lambda i: -_size(files[i]))
        _make_folder(out)
        outputs = [str(targets[i][0]) for i in todo]
        for i, row in zip(todo, _run(client, [files[i] for i in todo], outputs, params, progress)):
            rows[i] = row
    return pandas.DataFrame([r for r in rows if r is not None], columns=list(COLUMNS))


def _size(path: str) -> int:
    """A local file's size (0 for a URL: asking a remote store costs a request per file)."""
    try:
        return 0 if _is_url(path) else os.path.getsize(_local(path))
    except OSError:
        return 0


def _make_folder(out: str) -> None:
    if _is_url(out):
        import fsspec

        fs, path = fsspec.core.url_to_fs(out)
        fs.makedirs(path, exist_ok=True)
    else:
        os.makedirs(_local(out), exist_ok=True)


def _run(
    client: Any,
    inputs: Sequence[str],
    outputs: Sequence[str],
    params: dict[str, Any],
    progress: bool,
) -> list[dict[str, Any]]:
    """Runs one task per file on ``client`` (or a local cluster) and gives
    the rows in input order; a task lost with its worker is a failed row."""
    from distributed import Client, LocalCluster, as_completed
    from distributed import progress as show_progress

    own = None
    if client is None:
        cluster = LocalCluster(
            n_workers=os.cpu_count() or 1, threads_per_worker=1, processes=True
        )
        own = client = Client(cluster)
    try:
        futures = client.map(
            _mesh_task, list(inputs), list(outputs), params=params, pure=False
        )
        index = {f.key: k for k, f in enumerate(futures)}
        rows: list[dict[str, Any] | None] = [None] * len(futures)
        if progress:
            show_progress(futures)
        for future in as_completed(futures):
            k = index[future.key]
            try:
                rows[k] = future.result()
            except Exception as e:  # the worker died or the task was lost
                rows[k] = _row(inputs[k], outputs[k], "failed", error=f"{type(e).__name__}: {e}")
            future.release()
        return [r for r in rows if r is not None]
    finally:
        if own is not None:
            cluster = own.cluster
            own.close()
            if cluster is not None:
                cluster.close()


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m neuromesh_rs.distributed``: ``mesh_corpus`` from the shell.

    Exits with 0 when every file was meshed or skipped, 1 when one failed,
    4 when one mesh was written but is not sound (as ``neuromesh batch``).
    """
    parser = argparse.ArgumentParser(
        prog="python -m neuromesh_rs.distributed",
        description="Mesh many SWC files on a Dask cluster (local, SLURM, Kubernetes...).",
    )
    parser.add_argument("inputs", nargs="+", help="SWC files, folders, patterns or fsspec URLs")
    parser.add_argument("-o", "--out", required=True, help="output folder or fsspec URL")
    parser.add_argument(
        "--scheduler",
        help="address of a running Dask scheduler (tcp://HOST:8786); "
        "without it a local cluster with one worker per core is started",
    )
    parser.add_argument("--format", default="ply", choices=_native.FORMATS)
    parser.add_argument(
        "--no-skip-existing",
        dest="skip_existing",
        action="store_false",
        help="mesh every input again, even where its output exists",
    )
    parser.add_argument(
        "--summary", help="write the result table here (.csv, or .parquet with pyarrow)"
    )
    parser.add_argument("--progress", action="store_true", help="show Dask's progress bar")
    for name in _native.PARAM_NAMES:
        default = _native.DEFAULTS[name]
        parser.add_argument(
            "--" + name.replace("_", "-"),
            dest=name,
            type=type(default),
            default=None,
            help=f"meshing parameter (default {default}); see help(neuromesh_rs.mesh_swc)",
        )
    args = parser.parse_args(argv)
    params = {n: getattr(args, n) for n in _native.PARAM_NAMES if getattr(args, n) is not None}

    client = None
    if args.scheduler:
        from distributed import Client

        client = Client(args.scheduler)
    try:
        table = mesh_corpus(
            args.inputs,
            args.out,
            client=client,
            format=args.format,
            skip_existing=args.skip_existing,
            progress=args.progress,
            **params,
        )
    except (OSError, ValueError, TypeError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    finally:
        if client is not None:
            client.close()

    for row in table.itertuples(index=False):
        if row.warnings:
            for w in str(row.warnings).split("; "):
                print(f"warning: {row.input}: {w}", file=sys.stderr)
        if row.status in ("failed", "unsound"):
            print(f"error: {row.input}: {row.error}", file=sys.stderr)
    if args.summary:
        if args.summary.lower().endswith(".parquet"):
            table.to_parquet(args.summary, index=False)
        else:
            table.to_csv(args.summary, index=False)
    counts = table["status"].value_counts()
    said = ", ".join(f"{counts.get(s, 0)} {s}" for s in ("meshed", "skipped", "unsound", "failed"))
    print(f"{len(table)} files: {said}", file=sys.stderr)
    if counts.get("failed", 0):
        return 1
    if counts.get("unsound", 0):
        return 4
    return 0


if __name__ == "__main__":
    sys.exit(main())
