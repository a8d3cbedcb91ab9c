"""from_navis and from_morphio, on stand-ins shaped as those packages' objects
(and on the real packages where they are installed)."""

from __future__ import annotations

import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import neuromesh_rs


def morphio_like(path: Path) -> SimpleNamespace:
    """A MorphIO-shaped object for a single-point-soma SWC file: sections
    run between branch points and repeat their parent's last point."""
    m = neuromesh_rs.Morphology.from_swc(path)
    ids, parents, xyz, radii, types = m.ids, m.parents, m.xyz, m.radii, m.types
    index = {int(i): k for k, i in enumerate(ids)}
    children: dict[int, list[int]] = {}
    for k, p in enumerate(parents):
        if p >= 0:
            children.setdefault(index[int(p)], []).append(k)

    def section(first: int, start: int | None, is_root: bool) -> SimpleNamespace:
        chain = ([start] if start is not None else []) + [first]
        while len(children.get(chain[-1], [])) == 1:
            chain.append(children[chain[-1]][0])
        kids = [section(c, chain[-1], False) for c in children.get(chain[-1], [])]
        return SimpleNamespace(
            points=xyz[chain],
            diameters=2 * radii[chain],
            type=int(types[chain[-1]]),
            is_root=is_root,
            children=kids,
        )

    soma = int(np.flatnonzero(types == 1)[0])
    return SimpleNamespace(
        soma=SimpleNamespace(points=xyz[[soma]], diameters=2 * radii[[soma]]),
        root_sections=[section(c, None, True) for c in children.get(soma, [])],
    )


def test_from_morphio_rebuilds_the_tree(real_files: list[Path], small_cell: Path) -> None:
    pv = next(f for f in real_files if f.name.startswith("rat_CA1_PV"))
    for path in (small_cell, pv):
        ref = neuromesh_rs.Morphology.from_swc(path)
        m = neuromesh_rs.from_morphio(morphio_like(path))
        assert len(m) == len(ref)
        assert m.cable_length == pytest.approx(ref.cable_length, rel=1e-12)
        assert m.soma_kind == ref.soma_kind
        assert sorted(m.types) == sorted(ref.types)
        assert len(m.mesh().faces) == len(ref.mesh().faces)
    with pytest.raises(TypeError, match="morphio"):
        neuromesh_rs.from_morphio(object())


def test_from_navis_reads_the_node_table(small_cell: Path) -> None:
    pandas = pytest.importorskip("pandas")
    ref = neuromesh_rs.Morphology.from_swc(small_cell)
    nodes = pandas.DataFrame(
        {
            "node_id": ref.ids,
            "label": ref.types,
            "x": ref.xyz[:, 0],
            "y": ref.xyz[:, 1],
            "z": ref.xyz[:, 2],
            "radius": ref.radii,
            "parent_id": ref.parents,
        }
    )
    m = neuromesh_rs.from_navis(SimpleNamespace(nodes=nodes, soma=None))
    assert np.array_equal(m.ids, ref.ids) and np.array_equal(m.types, ref.types)
    # Without labels, the soma nodes navis names get type 1.
    soma_id = int(ref.ids[ref.types == 1][0])
    unlabelled = SimpleNamespace(nodes=nodes.drop(columns=["label"]), soma=soma_id)
    m = neuromesh_rs.from_navis(unlabelled)
    assert set(m.types) == {0, 1} and int(m.ids[m.types == 1][0]) == soma_id
    with pytest.raises(TypeError, match="TreeNeuron"):
        neuromesh_rs.from_navis(object())
    with pytest.raises(TypeError, match="parent_id"):
        neuromesh_rs.from_navis(SimpleNamespace(nodes=nodes.drop(columns=["parent_id"])))


def test_the_real_packages_agree_with_the_reader(small_cell: Path) -> None:
    navis = pytest.importorskip("navis")
    morphio = pytest.importorskip("morphio")
    ref = neuromesh_rs.Morphology.from_swc(small_cell)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = neuromesh_rs.from_navis(navis.read_swc(str(small_cell)))
        b = neuromesh_rs.from_morphio(morphio.Morphology(str(small_cell)))
    for m in (a, b):
        assert len(m) == len(ref)
        assert m.cable_length == pytest.approx(ref.cable_length, rel=1e-5)
