"""neuromesh_rs.distributed on a real two-worker LocalCluster.

The extra (``pip install neuromesh_rs[dask]``) is optional for users, so
these tests skip without it, except where ``NEUROMESH_REQUIRE_DASK`` is set
(``scripts/test`` sets it and installs the extra): there a missing extra
fails.
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

import neuromesh_rs

if os.environ.get("NEUROMESH_REQUIRE_DASK"):
    import distributed
    import pandas
else:
    distributed = pytest.importorskip("distributed")
    pandas = pytest.importorskip("pandas")

from neuromesh_rs import distributed as nd  # noqa: E402


@pytest.fixture(scope="module")
def client() -> Iterator[Any]:
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory, real_files: list[Path]) -> Path:
    """Ten real files (the smallest, to keep the test short) and a bad one."""
    d = tmp_path_factory.mktemp("in")
    for f in sorted(real_files, key=lambda p: p.stat().st_size)[:10]:
        shutil.copy(f, d / f.name)
    (d / "broken.swc").write_text("1 1 0 0 0 1 -1\n2 3 1 0 0 zero 1\n")
    return d


def test_a_folder_is_meshed_like_mesh_swc_and_a_bad_file_is_a_row(
    client: Any, folder: Path, tmp_path: Path
) -> None:
    out = tmp_path / "meshes"
    table = nd.mesh_corpus(folder, out, client=client)
    assert list(table.columns) == list(nd.COLUMNS)
    assert len(table) == 11
    assert table["input"].tolist() == sorted(str(p) for p in folder.glob("*.swc"))

    bad = table[table["input"].str.endswith("broken.swc")].iloc[0]
    assert bad["status"] == "failed"
    assert bad["error"].startswith("SwcError: ")
    assert "broken.swc:2:" in bad["error"]
    assert not (out / "broken.ply").exists()

    good = table[table["status"] != "failed"]
    assert len(good) == 10
    assert set(good["status"]) == {"meshed"}
    for row in good.itertuples(index=False):
        mesh = neuromesh_rs.mesh_swc(row.input)
        reference = tmp_path / "reference.ply"
        mesh.save(reference)
        assert Path(row.output).read_bytes() == reference.read_bytes(), row.input
        assert row.triangles == len(mesh.faces)
        assert row.samples == len(neuromesh_rs.Morphology.from_swc(row.input))
        assert row.area == pytest.approx(mesh.area, rel=1e-9)
        assert row.volume == pytest.approx(mesh.volume, rel=1e-9)
        assert row.seconds > 0

    # A second call meshes nothing: every output is there (the bad file is
    # tried again and fails again).
    stamps = {p.name: p.stat().st_mtime_ns for p in out.iterdir()}
    again = nd.mesh_corpus(folder, out, client=client)
    assert (again["status"] == "skipped").sum() == 10
    assert again.loc[again["status"] != "skipped", "input"].str.endswith("broken.swc").all()
    assert {p.name: p.stat().st_mtime_ns for p in out.iterdir()} == stamps


def test_the_command_line_runs_on_a_scheduler_and_writes_its_table(
    client: Any, folder: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    inputs = [str(p) for p in sorted(folder.glob("*.swc"))[:3]]
    summary = tmp_path / "result.csv"
    code = nd.main(
        [
            *inputs,
            "-o",
            str(tmp_path / "out"),
            "--scheduler",
            client.scheduler.address,
            "--format",
            "obj",
            "--resolution",
            "0.5",
            "--summary",
            str(summary),
        ]
    )
    table = pandas.read_csv(summary)
    assert table["input"].tolist() == inputs
    failed = table["status"] == "failed"
    assert code == (1 if failed.any() else 0)
    assert all(Path(p).suffix == ".obj" and Path(p).exists() for p in table.loc[~failed, "output"])
    # The parameter reached the workers: half the resolution, fewer triangles.
    one = table.loc[~failed].iloc[0]
    assert one["triangles"] < len(neuromesh_rs.mesh_swc(one["input"]).faces)
    assert f"{len(inputs)} files:" in capsys.readouterr().err


def test_urls_go_through_fsspec_and_messages_name_them(y_swc: Path, tmp_path: Path) -> None:
    fsspec = pytest.importorskip("fsspec")
    fs = fsspec.filesystem("memory")
    fs.pipe("/cells/y.swc", y_swc.read_bytes())
    fs.pipe("/cells/bad.swc", b"1 1 0 0 0 -1\n")
    fs.pipe("/cells/notes.txt", b"not a cell")
    # A folder URL gives its SWC files, a pattern its matches, as the CLI's rules.
    assert nd._expand("memory://cells") == ["memory:///cells/bad.swc", "memory:///cells/y.swc"]
    assert nd._expand(["memory://cells/y*"]) == ["memory:///cells/y.swc"]
    row = nd._mesh_task("memory://cells/y.swc", "memory://meshes/y.ply", {})
    assert row["status"] == "meshed", row
    reference = tmp_path / "y.ply"
    neuromesh_rs.mesh_swc(y_swc).save(reference)
    assert fs.cat("/meshes/y.ply") == reference.read_bytes()

    bad = nd._mesh_task("memory://cells/bad.swc", "memory://meshes/bad.ply", {})
    assert bad["status"] == "failed"
    assert bad["error"].startswith("SwcError: memory://cells/bad.swc:1:"), bad["error"]
    assert not fs.exists("/meshes/bad.ply")


def test_wrong_arguments_are_refused_before_any_work(folder: Path, tmp_path: Path) -> None:
    with pytest.raises(TypeError, match="resolutoin"):
        nd.mesh_corpus(folder, tmp_path, resolutoin=2.0)
    with pytest.raises(ValueError, match="resolution"):
        nd.mesh_corpus(folder, tmp_path, resolution=-1.0)
    with pytest.raises(ValueError, match="format"):
        nd.mesh_corpus(folder, tmp_path, format="vrml")
    with pytest.raises(FileNotFoundError):
        nd.mesh_corpus(tmp_path / "nowhere", tmp_path)
    assert not any(tmp_path.iterdir())
