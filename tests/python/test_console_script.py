"""The ``neuromesh`` command that ``pip install`` gives: the Rust command line."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from neuromesh_rs import _native

SCRIPT = Path(sys.executable).parent / "neuromesh"


def run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(SCRIPT), *args], capture_output=True, text=True, timeout=120)


def test_the_command_is_installed_and_explains_itself() -> None:
    assert SCRIPT.exists(), "pip install should put `neuromesh` next to the interpreter"
    done = run("--help")
    assert done.returncode == 0
    for command in ("mesh", "batch", "info", "check"):
        assert command in done.stdout
    assert "--resolution" in run("mesh", "--help").stdout


def test_it_meshes_and_fails_as_the_binary_does(y_swc: Path, tmp_path: Path) -> None:
    out = tmp_path / "y.ply"
    done = run("mesh", str(y_swc), "-o", str(out), "--check")
    assert done.returncode == 0, done.stderr
    assert out.stat().st_size > 0
    assert "sound                 yes" in done.stdout
    assert done.stdout.rstrip().splitlines()[-1].startswith("valid ")

    bad = tmp_path / "bad.swc"
    bad.write_text("1 1 0 0 0 1 -1\n2 3 1 0 0 one 1\n")
    done = run("mesh", str(bad), "-o", str(tmp_path / "bad.ply"))
    assert done.returncode == 1
    assert done.stderr.startswith(f"error: {bad}:2: ")
    assert run("mesh").returncode == 2


def test_usage_errors_and_help_do_not_end_the_interpreter(capfd: pytest.CaptureFixture[str]) -> None:
    assert _native._run_cli(["neuromesh", "--version"], False) == 0
    assert _native._run_cli(["neuromesh", "--no-such-flag"], False) == 2
    assert "neuromesh" in capfd.readouterr().out
