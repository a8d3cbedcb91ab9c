"""Morphologies from the objects of other packages (navis, MorphIO).

Neither package is imported here: the functions read the objects they are
given, so ``neuromesh_rs`` needs neither installed until a user has one.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._native import Morphology

__all__ = ["from_morphio", "from_navis"]


def from_navis(neuron: Any) -> Morphology:
    """A morphology from a navis ``TreeNeuron``.

    Parameters
    ----------
    neuron : navis.TreeNeuron
        Its node table (``neuron.nodes``: ``node_id``, ``parent_id``, ``x``,
        ``y``, ``z``, ``radius``, and ``label`` for the SWC type when the
        neuron was read from SWC) is taken as is; without ``label``, the
        nodes of ``neuron.soma`` get type 1 and the others 0.

    Returns
    -------
    Morphology
        In the neuron's units (navis keeps the file's; pass ``scale=`` when
        meshing). Missing (NaN) radii are filled as zero radii are, and
        warned.

    Raises
    ------
    TypeError
        ``neuron`` has no node table.
    SwcError
        The table does not form a forest (a missing parent, a repeated id).
    """
    nodes = getattr(neuron, "nodes", None)
    if nodes is None or not hasattr(nodes, "columns"):
        raise TypeError(f"neuron: expected a navis TreeNeuron (with .nodes), got {type(neuron).__name__}")
    missing = [c for c in ("node_id", "parent_id", "x", "y", "z") if c not in nodes.columns]
    if missing:
        raise TypeError(f"neuron: its node table lacks the column(s) {', '.join(missing)}")
    ids = nodes["node_id"].to_numpy(dtype=np.float64)
    if "label" in nodes.columns:
        types = nodes["label"].to_numpy(dtype=np.float64)
    else:
        soma = getattr(neuron, "soma", None)
        soma_ids = [] if soma is None else np.atleast_1d(np.asarray(soma, dtype=np.float64))
        types = np.where(np.isin(ids, soma_ids), 1.0, 0.0)
    radius = (
        nodes["radius"].to_numpy(dtype=np.float64)
        if "radius" in nodes.columns
        else np.full(len(ids), np.nan)
    )
    xyz = nodes[["x", "y", "z"]].to_numpy(dtype=np.float64)
    parents = nodes["parent_id"].to_numpy(dtype=np.float64)
    return Morphology.from_arrays(ids, types, xyz, radius, parents)


def from_morphio(morph: Any) -> Morphology:
    """A morphology from a MorphIO ``Morphology`` (immutable or mutable).

    Parameters
    ----------
    morph : morphio.Morphology
        The soma's points become type-1 samples, one after another; each
        root section hangs from the soma's first point, and each section's
        points follow, their radii half the diameters and their type the
        section's (2 axon, 3 basal, 4 apical dendrite, as in SWC). A child
        section's first point, which MorphIO repeats from its parent's last
        point, is not repeated.

    Returns
    -------
    Morphology
        In MorphIO's units (micrometres for the usual files).

    Raises
    ------
    TypeError
        ``morph`` has no soma or root sections.
    """
    soma = getattr(morph, "soma", None)
    roots = getattr(morph, "root_sections", None)
    if soma is None or roots is None:
        raise TypeError(
            f"morph: expected a morphio.Morphology (with .soma and .root_sections), got {type(morph).__name__}"
        )
    ids: list[int] = []
    types: list[int] = []
    xyz: list[np.ndarray] = []
    radii: list[float] = []
    parents: list[int] = []

    def add(point: np.ndarray, radius: float, kind: int, parent: int) -> int:
        ids.append(len(ids) + 1)
        types.append(kind)
        xyz.append(np.asarray(point, dtype=np.float64))
        radii.append(float(radius))
        parents.append(parent)
        return ids[-1]

    previous = -1
    soma_points = np.asarray(soma.points, dtype=np.float64).reshape(-1, 3)
    soma_diameters = np.asarray(soma.diameters, dtype=np.float64).reshape(-1)
    for point, diameter in zip(soma_points, soma_diameters):
        previous = add(point, diameter / 2.0, 1, previous)
    anchor = 1 if len(soma_points) else -1

    # Depth first, without recursion (a long neurite is thousands of sections).
    stack: list[tuple[Any, int]] = [(s, anchor) for s in reversed(list(roots))]
    while stack:
        section, parent = stack.pop()
        points = np.asarray(section.points, dtype=np.float64).reshape(-1, 3)
        diameters = np.asarray(section.diameters, dtype=np.float64).reshape(-1)
        kind = int(section.type)
        start = 0 if section.is_root else 1
        last = parent
        for point, diameter in zip(points[start:], diameters[start:]):
            last = add(point, diameter / 2.0, kind, last)
        for child in reversed(list(section.children)):
            stack.append((child, last))
    if not ids:
        raise TypeError("morph: the morphology has no points")
    return Morphology.from_arrays(
        np.array(ids, dtype=np.float64),
        np.array(types, dtype=np.float64),
        np.array(xyz).reshape(-1, 3),
        np.array(radii),
        np.array(parents, dtype=np.float64),
    )
