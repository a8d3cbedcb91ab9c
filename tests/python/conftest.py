"""Shared fixtures: paths to the repository's test data."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"
REAL = DATA / "real"


@pytest.fixture(scope="session")
def real_files() -> list[Path]:
    files = sorted(REAL.glob("*.swc"))
    assert len(files) == 48
    return files


@pytest.fixture(scope="session")
def y_swc() -> Path:
    return DATA / "y_bifurcation.swc"


@pytest.fixture(scope="session")
def small_cell() -> Path:
    return REAL / "rat_dentate_granule_1220882a.CNG.swc"
