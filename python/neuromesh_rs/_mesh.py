"""The ``Mesh`` and ``MeshReport`` classes: plain arrays with native methods."""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _native

if TYPE_CHECKING:  # pragma: no cover
    from ._native import Morphology

__all__ = ["Mesh", "MeshReport"]


@dataclass(frozen=True)
class MeshReport:
    """What :meth:`Mesh.check` found.

    ``closed``: every edge is in exactly two faces. ``manifold``: no edge in
    more than two faces and no pinched vertex. ``outward``: neighbouring faces
    agree on orientation and every component encloses positive volume.
    ``valid``: all of these, no degenerate or duplicate faces, and no
    self-intersections made by the construction. When the morphology is given,
    ``self_intersections`` is split into ``construction_intersections`` and
    ``skeleton_overlaps`` (branches far apart in the tree that pass through each
    other in space); otherwise both are ``None``.
    """

    vertices: int
    faces: int
    edges: int
    boundary_edges: int
    nonmanifold_edges: int
    misoriented_edges: int
    nonmanifold_vertices: int
    unreferenced_vertices: int
    degenerate_faces: int
    duplicate_faces: int
    components: int
    inward_components: int
    euler_characteristic: int
    area: float
    volume: float
    self_intersections: int
    construction_intersections: int | None
    skeleton_overlaps: int | None
    soma_area: float | None
    skeleton: dict[str, float] | None
    intersecting_pairs: list[tuple[int, int]]
    closed: bool
    manifold: bool
    outward: bool
    valid: bool


class Mesh:
    """A triangle mesh: float32 vertices ``(N, 3)`` and uint32 faces ``(M, 3)``.

    Faces wind counter-clockwise seen from outside. ``vertex_sample`` (uint32,
    ``(N,)``) holds the morphology sample index each vertex was made from, or
    is ``None`` for meshes built from arrays or read from OBJ/STL. The arrays are
    read-only views of the data the Rust core produced (no copy).

    Any mesh can be wrapped, for example a trimesh one, to use the checks:

    >>> import numpy as np
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
    >>> f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.uint32)
    >>> m = Mesh(v, f)
    >>> round(m.volume, 6), m.check().closed
    (0.166667, True)
    """

    __slots__ = ("_faces", "_stats", "_vertex_sample", "_vertices")

    def __init__(
        self,
        vertices: ArrayLike,
        faces: ArrayLike,
        vertex_sample: ArrayLike | None = None,
    ) -> None:
        v = np.ascontiguousarray(vertices, dtype=np.float32)
        f_in = np.asarray(faces)
        if f_in.size and (not np.issubdtype(f_in.dtype, np.integer) or f_in.min() < 0):
            raise ValueError("faces must hold non-negative integer vertex indices")
        f = np.ascontiguousarray(f_in, dtype=np.uint32)
        if v.ndim != 2 or v.shape[1] != 3:
            raise ValueError(f"vertices must have shape (n, 3), got {v.shape}")
        if f.ndim != 2 or f.shape[1] != 3:
            raise ValueError(f"faces must have shape (m, 3), got {f.shape}")
        if f.size and int(f.max()) >= len(v):
            raise ValueError(f"faces refer to vertex {int(f.max())} but there are only {len(v)} vertices")
        s = None
        if vertex_sample is not None:
            s = np.ascontiguousarray(vertex_sample, dtype=np.uint32)
            if s.shape != (len(v),):
                raise ValueError(f"vertex_sample must have shape ({len(v)},), got {s.shape}")
        self._set(v, f, s, {})

    @classmethod
    def _from_native(
        cls,
        vertices: NDArray[np.float32],
        faces: NDArray[np.uint32],
        vertex_sample: NDArray[np.uint32],
        stats: dict[str, int],
    ) -> Mesh:
        mesh = cls.__new__(cls)
        sample = vertex_sample if len(vertex_sample) == len(vertices) and len(vertices) else None
        mesh._set(vertices, faces, sample, stats)
        return mesh

    def _set(
        self,
        vertices: NDArray[np.float32],
        faces: NDArray[np.uint32],
        vertex_sample: NDArray[np.uint32] | None,
        stats: dict[str, int],
    ) -> None:
        for a in (vertices, faces, vertex_sample):
            if a is not None:
                a.setflags(write=False)
        self._vertices = vertices
        self._faces = faces
        self._vertex_sample = vertex_sample
        self._stats = dict(stats)

    @property
    def vertices(self) -> NDArray[np.float32]:
        """Vertex positions, float32, shape ``(N, 3)``, read-only."""
        return self._vertices

    @property
    def faces(self) -> NDArray[np.uint32]:
        """Triangles as vertex indices, uint32, shape ``(M, 3)``, read-only."""
        return self._faces

    @property
    def vertex_sample(self) -> NDArray[np.uint32] | None:
        """Morphology sample index of each vertex, or ``None`` if unknown."""
        return self._vertex_sample

    @property
    def stats(self) -> dict[str, int]:
        """How the mesh was built: branches, skipped contours, junctions by method, crossing pairs of parts found and left after the union."""
        return dict(self._stats)

    @property
    def area(self) -> float:
        """Surface area (in squared units of the coordinates)."""
        return float(_native._mesh_area(self._vertices, self._faces))

    @property
    def volume(self) -> float:
        """Signed enclosed volume; positive for a closed, outward mesh."""
        return float(_native._mesh_volume(self._vertices, self._faces))

    def check(self, morphology: Morphology | None = None) -> MeshReport:
        """Check closedness, manifoldness, orientation and self-intersections.

        Parameters
        ----------
        morphology
            The morphology the mesh was made from. With it (and sample labels),
            self-intersections are split into those the construction made and
            those where the skeleton itself overlaps.

        Returns
        -------
        MeshReport
        """
        d: dict[str, Any] = _native._mesh_check(self._vertices, self._faces, self._vertex_sample, morphology)
        return MeshReport(**d)

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write the mesh; the extension (``.obj``, ``.ply``, ``.stl``) picks the format.

        PLY keeps ``vertex_sample`` as a per-vertex ``sample`` property. The file is
        written to a temporary name and renamed, so a failed write leaves nothing
        half-written.

        Raises
        ------
        ValueError
            For an unknown extension.
        OSError
            When the file cannot be written.
        """
        _native._mesh_save(self._vertices, self._faces, os.fspath(path), self._vertex_sample)

    def to_trimesh(self) -> Any:
        """The mesh as a ``trimesh.Trimesh`` (requires ``pip install trimesh``)."""
        try:
            import trimesh
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("to_trimesh() needs trimesh: pip install trimesh") from e
        return trimesh.Trimesh(vertices=self._vertices, faces=self._faces, process=False)

    def __len__(self) -> int:
        return int(self._faces.shape[0])

    def __repr__(self) -> str:
        return f"Mesh(vertices={len(self._vertices)}, faces={len(self._faces)})"

    def __getstate__(self) -> dict[str, Any]:
        return {
            "vertices": np.array(self._vertices),
            "faces": np.array(self._faces),
            "vertex_sample": None if self._vertex_sample is None else np.array(self._vertex_sample),
            "stats": self._stats,
        }

    def __setstate__(self, state: dict[str, Any]) -> None:
        self._set(state["vertices"], state["faces"], state["vertex_sample"], state["stats"])
