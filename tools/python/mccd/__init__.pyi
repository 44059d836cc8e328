"""Type stubs of the mccd module (continuous collision detection between deforming triangle
meshes). The docstrings of the module itself (help(mccd.Scene)) say the same at length."""
import os
from typing import Any, Callable, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str
#: the SIMD kernels in use: "avx512", "avx2", "sse2" or "scalar"
simd_level: str

#: ``kind`` of a vertex-face contact: ``a`` a vertex of ``mesh_a``, ``b`` a face of ``mesh_b``
VERTEX_FACE: int
#: ``kind`` of an edge-edge contact: ``a`` and ``b`` edges
EDGE_EDGE: int
#: the record of a contact: kind (u1), mesh_a, a, mesh_b, b (u4), vertices (u4, 4), toi (f8);
#: the itemsize and offsets of the C++ struct mccd::Contact, whose memory the arrays use
CONTACT_DTYPE: np.dtype
#: the record of a step of run(): step, vf, ee (u8), first_impact, seconds (f8)
RUN_STEP_DTYPE: np.dtype

PathLike = Union[str, "os.PathLike[str]"]
#: an n x 3 position array: read in place when float64 or float32 with positive strides that
#: are multiples of the item size (C or Fortran order); anything else is converted once
Positions = npt.ArrayLike
#: one position array per mesh (None for a static mesh), or one array for a scene of one mesh
PerMesh = Union[Sequence[Positions | None], np.ndarray]
#: (V, F) or (V, F, name): V n x 3 coordinates (copied), F m x 3 integer vertex indices (copied)
MeshTuple = Union[Tuple[npt.ArrayLike, npt.ArrayLike], Tuple[npt.ArrayLike, npt.ArrayLike, str]]

class Error(ValueError):
    """Raised for every refused input (a mesh, an array, an option, a file), with the
    library's message naming the mesh, the array or file and what is wrong. Nothing has
    changed when it is raised."""

class StepResult:
    """What a step found: ``contacts`` (structured array, dtype CONTACT_DTYPE, canonical
    order, owning the C++ result's memory), ``earliest_toi`` (inf when none) and ``stats``
    (counts and stage times t_* in seconds)."""

    @property
    def contacts(self) -> np.ndarray: ...
    @property
    def earliest_toi(self) -> float: ...
    @property
    def stats(self) -> dict[str, Any]: ...
    def __len__(self) -> int: ...

class Scene:
    """A scene of triangle meshes, stepped over time. The meshes are copied; position
    arguments of step(), advance() and the queries are read in place when float64 or float32
    (C or Fortran order), converted once otherwise, and held until the call returns. A step
    releases the GIL; one scene steps one call at a time (a concurrent call raises Error)."""

    def __init__(
        self,
        meshes: Sequence[MeshTuple],
        *,
        method: str = "fbd",
        threads: int | None = None,
        min_distance: float = 0.0,
        static: bool | Sequence[bool] | None = None,
        self_collision: bool | Sequence[bool] | None = None,
        volume: str = "kdop18",
        bvh: str = "sah",
        leaf_size: int = 0,
        representatives: str = "default",
        self_culling: bool = True,
        max_front_bytes: int = 0,
        work_span: bool = False,
    ) -> None:
        """method: "fbd" (default), "phc", "traverse" or "bruteforce" (identical contacts);
        threads: None (the caller's oneTBB arena) or the size of the scene's own arena;
        static / self_collision: a bool or one per mesh."""
    def step(self, start: PerMesh, end: PerMesh, *, method: str | None = None) -> StepResult:
        """One step from start to end (one array per mesh); end becomes the start of the next
        advance()."""
    def advance(self, next: PerMesh, *, method: str | None = None) -> StepResult:
        """One step from the last end positions (initially the meshes' V) to next."""
    def is_collision_free(self, start: PerMesh, end: PerMesh) -> bool:
        """Whether nothing touches during the step; leaves the scene as it was."""
    def earliest_impact(self, start: PerMesh, end: PerMesh) -> float:
        """The earliest time of impact in [0, 1] (inf when collision free), equal to
        step(start, end).earliest_toi; leaves the scene as it was."""
    def candidates(self, start: PerMesh, end: PerMesh) -> np.ndarray:
        """The broad phase's feature pairs, untested (dtype CONTACT_DTYPE, toi a lower bound
        of any contact time); leaves the scene as it was."""
    def mesh(self, i: int) -> Tuple[np.ndarray, np.ndarray, str]:
        """Mesh i's initial positions (float64) and faces (uint32), read-only views of the
        scene's arrays, and its name."""
    @property
    def num_meshes(self) -> int: ...
    @property
    def threads(self) -> int | None: ...
    @property
    def method(self) -> str: ...
    @property
    def bvh_depth(self) -> int: ...
    # testing aids
    def _last_view_data(self) -> list[Tuple[int, int]]: ...
    def _set_step_hook(self, hook: Callable[[], None] | None) -> None: ...
    def _time_cpp_step(self, start: PerMesh, end: PerMesh) -> Tuple[float, float, int]: ...

class RunResult:
    """What run() found: ``steps`` (one record per step, dtype RUN_STEP_DTYPE) and
    ``summary`` (totals)."""

    @property
    def steps(self) -> np.ndarray: ...
    @property
    def summary(self) -> dict[str, Any]: ...
    def __len__(self) -> int: ...

def load_mesh(path: PathLike) -> Tuple[np.ndarray, np.ndarray]:
    """Reads an OBJ or PLY file: V (n x 3 float64) and F (m x 3 uint32), owning the memory
    the reader filled."""

def save_mesh(path: PathLike, V: npt.ArrayLike, F: npt.ArrayLike) -> None:
    """Writes a binary PLY or an OBJ (by extension); a failed write leaves no file."""

def make_scene(name: str, size: int = 4, frames: int = 31) -> Tuple[list[Tuple[np.ndarray, np.ndarray, str]], list[list[np.ndarray]]]:
    """A built-in animated scene ("cloth", "spheres", "random", "tube", "drape") of about
    ``size`` thousand triangles: (meshes, frames), frames[k] one array per mesh."""

def run(
    frames: PathLike | Sequence[PathLike] | None = None,
    *,
    scene: str | None = None,
    size: int = 4,
    frame_count: int = 31,
    method: str = "fbd",
    threads: int | None = None,
    substeps: int = 1,
    min_distance: float = 0.0,
    contacts: PathLike | None = None,
    stats: PathLike | None = None,
    partial: str = "keep",
    image: PathLike | None = None,
    image_step: int | None = None,
    image_size: Tuple[int, int] = (1200, 900),
    camera: str | None = None,
    colored: PathLike | None = None,
    volume: str = "kdop18",
    bvh: str = "sah",
    leaf_size: int = 0,
    representatives: str = "default",
    self_culling: bool = True,
) -> RunResult:
    """The command `mccd run`: steps every frame k -> k + 1 of frame files (a list, a
    printf pattern or a folder) or of a built-in scene, writing the command's CSV/JSON
    contacts, JSON statistics and pictures, and returns one record per step."""
