"""The ``Mesh`` and ``MeshReport`` classes: plain arrays with native methods."""

from __future__ import annotations

import os
import warnings
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
    ``sound``: all of these, no degenerate or duplicate faces, and no
    self-intersection at all. When the morphology is given,
    ``self_intersections`` is split into ``construction_intersections`` and
    ``skeleton_overlaps`` (branches far apart in the tree that pass through each
    other in space), and ``fidelity`` compares the mesh point by point with the
    union of the skeleton's round cones: ``samples`` tested (every neurite
    sample and each soma's centre), ``samples_outside`` and the first of them
    (``outside``), the vertices' ``deviation_radii`` (median, 95th percentile,
    worst, in local radii), ``deviation`` (the same in file units) and ``sme``
    (their mean, in file units); ``faithful`` says every sample is inside and
    the worst and 95th-percentile deviations are within 0.25 and 0.05 local
    radii. Without a morphology those are ``None`` and ``faithful`` is true.
    ``valid``: sound and faithful.
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
    fidelity: dict[str, Any] | None
    intersecting_pairs: list[tuple[int, int]]
    closed: bool
    manifold: bool
    outward: bool
    sound: bool
    faithful: bool
    valid: bool


class Mesh:
    """A triangle mesh: vertices ``(N, 3)`` and uint32 faces ``(M, 3)``.

    Faces wind counter-clockwise seen from outside. ``vertex_sample`` (uint32,
    ``(N,)``) holds the morphology sample index each vertex was made from, or
    is ``None`` for meshes built from arrays or read from OBJ/STL. The arrays are
    read-only views of the data the Rust core produced (no copy).

    Positions are stored as float32 relative to ``origin``. For most cells
    ``origin`` is ``(0, 0, 0)`` and ``vertices`` is that float32 array. A cell
    far from the coordinates' origin compared with its size (atlas coordinates
    such as MouseLight's, ~10⁴ µm) is meshed around a point near its centre,
    since float32 positions at 10⁴ would round a thin neurite's triangles into
    each other; ``vertices`` then gives float64 absolute positions
    (``local_vertices + origin``) and ``local_vertices`` the float32 ones.

    Any mesh can be wrapped, for example a trimesh one, to use the checks:

    >>> import numpy as np
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
    >>> f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.uint32)
    >>> m = Mesh(v, f)
    >>> round(m.volume, 6), m.check().closed
    (0.166667, True)
    """

    __slots__ = ("_absolute", "_faces", "_origin", "_stats", "_vertex_sample", "_vertices")

    def __init__(
        self,
        vertices: ArrayLike,
        faces: ArrayLike,
        vertex_sample: ArrayLike | None = None,
    ) -> None:
        v_in = np.asarray(vertices)
        origin = (0.0, 0.0, 0.0)
        # Only positions finer than float32 can gain from a local frame.
        wide = v_in.dtype.kind == "f" and v_in.dtype.itemsize > 4
        if wide and v_in.ndim == 2 and v_in.shape[1] == 3 and len(v_in) and np.isfinite(v_in).all():
            origin = _native._frame_origin(tuple(v_in.min(axis=0)), tuple(v_in.max(axis=0)))
        if origin == (0.0, 0.0, 0.0):
            v = np.ascontiguousarray(v_in, dtype=np.float32)
        else:
            v = np.ascontiguousarray(v_in - np.asarray(origin), dtype=np.float32)
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
        self._set(v, f, s, {}, origin)

    @classmethod
    def _from_native(
        cls,
        vertices: NDArray[np.float32],
        faces: NDArray[np.uint32],
        vertex_sample: NDArray[np.uint32],
        stats: dict[str, int],
        origin: tuple[float, float, float],
    ) -> Mesh:
        mesh = cls.__new__(cls)
        sample = vertex_sample if len(vertex_sample) == len(vertices) and len(vertices) else None
        mesh._set(vertices, faces, sample, stats, origin)
        return mesh

    def _set(
        self,
        vertices: NDArray[np.float32],
        faces: NDArray[np.uint32],
        vertex_sample: NDArray[np.uint32] | None,
        stats: dict[str, int],
        origin: tuple[float, float, float],
    ) -> None:
        for a in (vertices, faces, vertex_sample):
            if a is not None:
                a.setflags(write=False)
        self._vertices = vertices
        self._faces = faces
        self._vertex_sample = vertex_sample
        self._stats = dict(stats)
        self._origin = (float(origin[0]), float(origin[1]), float(origin[2]))
        self._absolute: NDArray[np.float64] | None = None

    @property
    def vertices(self) -> NDArray[np.float32] | NDArray[np.float64]:
        """Vertex positions, shape ``(N, 3)``, read-only: float32, or float64
        (``local_vertices + origin``) when ``origin`` is not zero."""
        if self._origin == (0.0, 0.0, 0.0):
            return self._vertices
        if self._absolute is None:
            a = self._vertices.astype(np.float64) + np.asarray(self._origin)
            a.setflags(write=False)
            self._absolute = a
        return self._absolute

    @property
    def local_vertices(self) -> NDArray[np.float32]:
        """Vertex positions relative to ``origin``, float32, read-only."""
        return self._vertices

    @property
    def origin(self) -> tuple[float, float, float]:
        """The point ``local_vertices`` are measured from: ``(0, 0, 0)``
        unless the mesh lies far from the coordinates' origin compared with
        its size."""
        return self._origin

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
        """How the mesh was built and what was changed in its input.

        Branches, skipped contours, junctions by method, crossing pairs of
        parts found and left after the union, fillers; and the changes to
        the geometry the file gives: ``samples_merged``, ``radii_filled``,
        ``soma_radii_replaced``, ``radii_raised`` (to the radius floor).
        """
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
        d: dict[str, Any] = _native._mesh_check(
            self._vertices, self._faces, self._vertex_sample, morphology, self._origin
        )
        return MeshReport(**d)

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write the mesh; the extension (``.obj``, ``.ply``, ``.stl``) picks the format.

        PLY keeps ``vertex_sample`` as a per-vertex ``sample`` property. The file is
        written to a temporary name and renamed, so a failed write leaves nothing
        half-written. A mesh with a non-zero ``origin`` is written with the origin
        added, in double precision to OBJ and PLY; STL holds only float32, so
        saving such a mesh as STL warns that thin neurites may be rounded into
        each other.

        Raises
        ------
        ValueError
            For an unknown extension.
        OSError
            When the file cannot be written.
        """
        target = os.fspath(path)
        if self._origin != (0.0, 0.0, 0.0) and target.lower().endswith(".stl"):
            warnings.warn(
                f"{target}: STL stores float32 coordinates, which round this mesh "
                f"(origin {self._origin}) more coarsely than it was built; "
                "save as .obj or .ply to keep it exact",
                stacklevel=2,
            )
        _native._mesh_save(self._vertices, self._faces, target, self._vertex_sample, self._origin)

    def to_trimesh(self, morphology: Morphology | None = None) -> Any:
        """The mesh as a ``trimesh.Trimesh`` (requires ``pip install trimesh``).

        Parameters
        ----------
        morphology : Morphology, optional
            The morphology the mesh was made from. With it, each vertex also
            gets its sample's SWC type.

        Returns
        -------
        trimesh.Trimesh
            Unprocessed (vertices and faces as they are), with the vertex
            attribute ``sample`` (the morphology sample each vertex was made
            from) when the mesh knows it, and ``type`` (the sample's SWC type:
            1 soma, 2 axon, 3 basal, 4 apical dendrite...) when
            ``morphology`` is given.

        Raises
        ------
        ValueError
            ``morphology`` given for a mesh without sample labels, or one
            whose samples do not cover the labels.
        """
        try:
            import trimesh
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("to_trimesh() needs trimesh: pip install trimesh") from e
        attributes: dict[str, NDArray[Any]] = {}
        sample = self._vertex_sample
        if sample is not None:
            attributes["sample"] = np.array(sample)
        if morphology is not None:
            attributes["type"] = self._vertex_types(morphology)
        return trimesh.Trimesh(
            vertices=self.vertices, faces=self._faces, vertex_attributes=attributes, process=False
        )

    def _vertex_types(self, morphology: Morphology) -> NDArray[np.int32]:
        """Each vertex's SWC type, through ``vertex_sample`` into ``morphology``."""
        sample = self._vertex_sample
        if sample is None:
            raise ValueError("morphology: this mesh has no sample labels to give types from")
        types = np.asarray(morphology.types)
        if len(sample) and int(sample.max()) >= len(types):
            raise ValueError(
                f"morphology: the mesh's labels reach sample {int(sample.max())}, "
                f"but the morphology has {len(types)} samples"
            )
        return types[sample]

    def split_by_type(self, morphology: Morphology) -> dict[int, Mesh]:
        """The mesh cut into one piece per SWC type (soma, axon, basal, apical...).

        Parameters
        ----------
        morphology : Morphology
            The morphology the mesh was made from (its types label the
            vertices through ``vertex_sample``).

        Returns
        -------
        dict of int to Mesh
            For each type present, the faces most of whose vertices have it,
            with only the vertices they use. Together the pieces are the whole
            mesh, face for face. A piece is closed only when its type makes up
            a whole component: where two types meet (a dendrite leaving the
            soma) each piece is **open** along the seam, so areas add up but
            volumes of pieces are not meaningful; ``check()`` reports the
            boundary edges.

        Raises
        ------
        ValueError
            The mesh has no sample labels, or its labels reach past the
            morphology's samples.
        """
        corner = self._vertex_types(morphology)[self._faces]
        sample = self._vertex_sample
        assert sample is not None  # _vertex_types refused a mesh without labels
        # The majority type of each face's three corners (the first when all differ).
        face_type = np.where(
            (corner[:, 1] == corner[:, 2]) & (corner[:, 0] != corner[:, 1]), corner[:, 1], corner[:, 0]
        )
        pieces: dict[int, Mesh] = {}
        for t in np.unique(face_type):
            faces = self._faces[face_type == t]
            used, local = np.unique(faces, return_inverse=True)
            piece = Mesh.__new__(Mesh)
            piece._set(
                np.ascontiguousarray(self._vertices[used]),
                np.ascontiguousarray(local.reshape(-1, 3), dtype=np.uint32),
                np.ascontiguousarray(sample[used]),
                {},
                self._origin,
            )
            pieces[int(t)] = piece
        return pieces

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
            "origin": self._origin,
        }

    def __setstate__(self, state: dict[str, Any]) -> None:
        origin = state.get("origin", (0.0, 0.0, 0.0))
        self._set(state["vertices"], state["faces"], state["vertex_sample"], state["stats"], origin)
