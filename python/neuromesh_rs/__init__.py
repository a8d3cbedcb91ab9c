"""neuromesh_rs: closed, manifold triangle meshes of neurons from SWC skeletons.

The heavy lifting is a Rust core (the ``neuromesh`` crate); this package is its
Python face. Typical use::

    >>> import neuromesh_rs
    >>> mesh = neuromesh_rs.mesh_swc("tests/data/y_bifurcation.swc")
    >>> mesh.vertices.dtype, mesh.faces.dtype
    (dtype('float32'), dtype('uint32'))

Coordinates stay in the SWC's own units (often micrometres, sometimes nanometres
or voxels); pass ``scale=`` to convert. Vertices are float32 ``(N, 3)``, faces
uint32 ``(M, 3)``, and ``mesh.vertex_sample`` gives the morphology sample each
vertex was made from, so per-sample values (voltage, calcium, type) map onto the
surface.
"""

from ._convert import from_morphio as from_morphio
from ._convert import from_navis as from_navis
from ._mesh import Mesh as Mesh
from ._mesh import MeshReport as MeshReport
from ._native import DEFAULTS as DEFAULTS
from ._native import PARAM_NAMES as PARAM_NAMES
from ._native import MeshError as MeshError
from ._native import MeshFileError as MeshFileError
from ._native import Morphology as Morphology
from ._native import SwcError as SwcError
from ._native import __version__ as __version__
from ._native import load_mesh as load_mesh
from ._native import mesh_many as mesh_many
from ._native import mesh_swc as mesh_swc

__all__ = [
    "DEFAULTS",
    "PARAM_NAMES",
    "Mesh",
    "MeshError",
    "MeshFileError",
    "MeshReport",
    "Morphology",
    "SwcError",
    "__version__",
    "from_morphio",
    "from_navis",
    "load_mesh",
    "mesh_many",
    "mesh_swc",
]
