"""The public surface: names, version, parameter names and defaults."""

from __future__ import annotations

import inspect
from pathlib import Path

import pytest

import neuromesh_rs
from neuromesh_rs import _native


def test_all_names_exist() -> None:
    for name in neuromesh_rs.__all__:
        assert hasattr(neuromesh_rs, name), name


def test_version_is_the_crate_version() -> None:
    assert neuromesh_rs.__version__.count(".") == 2


def test_keyword_arguments_match_the_rust_params() -> None:
    # The CLI flags derive from the same Params struct; PARAM_NAMES is its list.
    names = list(_native.PARAM_NAMES)
    assert set(names) == set(neuromesh_rs.DEFAULTS)
    for fn in (neuromesh_rs.mesh_swc, neuromesh_rs.Morphology.mesh):
        sig = inspect.signature(fn)
        kw = [p.name for p in sig.parameters.values() if p.kind is inspect.Parameter.KEYWORD_ONLY]
        assert kw == names, fn
        for p in sig.parameters.values():
            # PyO3 shows non-literal defaults as `...`; literal ones must match.
            if p.name in neuromesh_rs.DEFAULTS and p.default is not Ellipsis:
                assert p.default == neuromesh_rs.DEFAULTS[p.name], p.name


def test_defaults_are_the_documented_ones() -> None:
    assert neuromesh_rs.DEFAULTS == {
        "angle_threshold": 10.0,
        "k1": 1,
        "min_vertices": 12,
        "max_vertices": 64,
        "cap_rings": 3,
        "resolution": 1.0,
        "min_radius": 0.0,
        "scale": 1.0,
        "face_limit": 100_000_000,
    }


def test_exceptions_subclass_builtins() -> None:
    assert issubclass(neuromesh_rs.SwcError, ValueError)
    assert issubclass(neuromesh_rs.MeshFileError, ValueError)
    assert issubclass(neuromesh_rs.MeshError, RuntimeError)


def test_mesh_many_says_when_given_one_path(tmp_path: Path) -> None:
    with pytest.raises(TypeError, match=r"single path: pass \[path\]"):
        neuromesh_rs.mesh_many("cell.swc")
    with pytest.raises(TypeError, match="single path"):
        neuromesh_rs.mesh_many(tmp_path / "cell.swc")
    with pytest.raises(TypeError, match="sequence of str or os.PathLike, got int"):
        neuromesh_rs.mesh_many(3)  # type: ignore[arg-type]
