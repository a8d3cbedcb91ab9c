"""Type stubs for the Rust extension ``neuromesh_rs._native`` (checked by mypy.stubtest)."""

import os
from collections.abc import Callable, Sequence
from typing import Any, Literal, final, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._mesh import Mesh

__all__ = [
    "DEFAULTS",
    "FORMATS",
    "PARAM_NAMES",
    "MeshError",
    "MeshFileError",
    "Morphology",
    "SwcError",
    "__version__",
    "_check_params",
    "_expand_inputs",
    "_mesh_area",
    "_mesh_file",
    "_mesh_check",
    "_mesh_save",
    "_frame_origin",
    "_mesh_volume",
    "_output_paths",
    "_run_cli",
    "load_mesh",
    "mesh_many",
    "mesh_swc",
]

__version__: str
PARAM_NAMES: list[str]
DEFAULTS: dict[str, float | int]
FORMATS: list[str]

class SwcError(ValueError):
    """A malformed SWC file or array input; ``path`` and ``line`` say where."""

    path: str
    line: int
    reason: str

class MeshFileError(ValueError):
    """A mesh file (OBJ, PLY, STL) that cannot be understood."""

class MeshError(RuntimeError):
    """An internal failure of the mesher: a bug; please report it with the input."""

@final
class Morphology:
    """A neuron skeleton: samples, tree and soma (SWC ids only at the edge)."""

    @staticmethod
    def from_swc(path: str | os.PathLike[str]) -> Morphology:
        """Reads an SWC file."""
    @staticmethod
    def from_arrays(
        ids: ArrayLike,
        types: ArrayLike,
        xyz: ArrayLike,
        radii: ArrayLike,
        parents: ArrayLike,
    ) -> Morphology:
        """Builds a morphology from columns; ``parents`` holds parent ids (negative for roots)."""
    @property
    def ids(self) -> NDArray[np.int64]:
        """SWC ids (int64)."""
    @property
    def types(self) -> NDArray[np.int32]:
        """SWC type codes (int32)."""
    @property
    def xyz(self) -> NDArray[np.float64]:
        """Positions, shape (n, 3), float64."""
    @property
    def radii(self) -> NDArray[np.float64]:
        """Cleaned radii (float64, all > 0)."""
    @property
    def parents(self) -> NDArray[np.int64]:
        """Parent ids as the file links them (-1 for roots), int64."""
    @property
    def name(self) -> str:
        """The file name, or ``<arrays>``."""
    @property
    def soma_kind(self) -> str:
        """``"none"``, ``"single point"``, ``"three-point"`` or ``"multi-point (contour or stack)"``."""
    @property
    def soma_center(self) -> tuple[float, float, float] | None:
        """Soma centre ``(x, y, z)`` or None."""
    @property
    def soma_radius(self) -> float | None:
        """Soma radius (NeuroM's definition) or None."""
    @property
    def n_trees(self) -> int:
        """Number of connected trees."""
    @property
    def cable_length(self) -> float:
        """Total neurite cable length."""
    @property
    def cleaning(self) -> dict[str, int]:
        """What cleaning changed, as a dict of counts."""
    def summary(self) -> str:
        """The ``neuromesh info`` summary as text."""
    def mesh(
        self,
        *,
        # params:begin
        angle_threshold: float = 10.0,
        k1: int = 1,
        min_vertices: int = 12,
        max_vertices: int = 64,
        cap_rings: int = 3,
        resolution: float = 1.0,
        min_radius: float = 0.0,
        scale: float = 1.0,
        face_limit: int = 100_000_000,
        # params:end
    ) -> Mesh:
        """Meshes the morphology into a ``neuromesh_rs.Mesh``."""
    def __len__(self) -> int: ...

def mesh_swc(
    path: str | os.PathLike[str],
    *,
    # params:begin
    angle_threshold: float = 10.0,
    k1: int = 1,
    min_vertices: int = 12,
    max_vertices: int = 64,
    cap_rings: int = 3,
    resolution: float = 1.0,
    min_radius: float = 0.0,
    scale: float = 1.0,
    face_limit: int = 100_000_000,
    # params:end
) -> Mesh:
    """Reads an SWC file and meshes it into a ``neuromesh_rs.Mesh``."""

@overload
def mesh_many(
    paths: Sequence[str | os.PathLike[str]],
    *,
    threads: int | None = None,
    return_exceptions: Literal[False] = False,
    progress: bool | Callable[[int, int], object] | None = None,
    # params:begin
    angle_threshold: float = 10.0,
    k1: int = 1,
    min_vertices: int = 12,
    max_vertices: int = 64,
    cap_rings: int = 3,
    resolution: float = 1.0,
    min_radius: float = 0.0,
    scale: float = 1.0,
    face_limit: int = 100_000_000,
    # params:end
) -> list[Mesh]:
    """Meshes many SWC files in parallel, detached from the interpreter; the
    results come back in input order, and the first failed file's exception is raised."""

@overload
def mesh_many(
    paths: Sequence[str | os.PathLike[str]],
    *,
    threads: int | None = None,
    return_exceptions: Literal[True],
    progress: bool | Callable[[int, int], object] | None = None,
    # params:begin
    angle_threshold: float = 10.0,
    k1: int = 1,
    min_vertices: int = 12,
    max_vertices: int = 64,
    cap_rings: int = 3,
    resolution: float = 1.0,
    min_radius: float = 0.0,
    scale: float = 1.0,
    face_limit: int = 100_000_000,
    # params:end
) -> list[Mesh | Exception]:
    """Meshes many SWC files in parallel, detached from the interpreter; the
    results come back in input order, a failed file as its exception."""

def _mesh_file(
    input: str | os.PathLike[str],
    output: str | os.PathLike[str],
    *,
    threads: int = 1,
    # params:begin
    angle_threshold: float = 10.0,
    k1: int = 1,
    min_vertices: int = 12,
    max_vertices: int = 64,
    cap_rings: int = 3,
    resolution: float = 1.0,
    min_radius: float = 0.0,
    scale: float = 1.0,
    face_limit: int = 100_000_000,
    # params:end
) -> dict[str, Any]: ...
def _check_params(
    *,
    # params:begin
    angle_threshold: float = 10.0,
    k1: int = 1,
    min_vertices: int = 12,
    max_vertices: int = 64,
    cap_rings: int = 3,
    resolution: float = 1.0,
    min_radius: float = 0.0,
    scale: float = 1.0,
    face_limit: int = 100_000_000,
    # params:end
) -> None: ...
def _expand_inputs(inputs: Sequence[str | os.PathLike[str]]) -> list[str]: ...
def _output_paths(
    inputs: Sequence[str | os.PathLike[str]], out_dir: str | os.PathLike[str], ext: str
) -> list[tuple[str | None, str | None]]: ...
def _run_cli(args: list[str], handle_signals: bool) -> int: ...
def load_mesh(path: str | os.PathLike[str]) -> Mesh:
    """Reads an OBJ, PLY or STL file into a ``neuromesh_rs.Mesh``."""

def _mesh_area(vertices: NDArray[np.float32], faces: NDArray[np.uint32]) -> float: ...
def _mesh_volume(vertices: NDArray[np.float32], faces: NDArray[np.uint32]) -> float: ...
def _mesh_check(
    vertices: NDArray[np.float32],
    faces: NDArray[np.uint32],
    vertex_sample: NDArray[np.uint32] | None = None,
    morphology: Morphology | None = None,
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> dict[str, Any]: ...
def _mesh_save(
    vertices: NDArray[np.float32],
    faces: NDArray[np.uint32],
    path: str | os.PathLike[str],
    vertex_sample: NDArray[np.uint32] | None = None,
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> None: ...
def _frame_origin(
    lo: tuple[float, float, float], hi: tuple[float, float, float]
) -> tuple[float, float, float]: ...
