"""Continuous collision detection between deforming triangle meshes (the C++ library mccd).

Every vertex moves on a straight line over a time step; a step reports every vertex-face and
edge-edge pair that touches during it, each with a conservative time of impact in [0, 1]:

    import mccd
    V0, F = mccd.load_mesh("cloth_ball92.ply")
    V1, _ = mccd.load_mesh("cloth_ball93.ply")
    scene = mccd.Scene([(V0, F)])
    r = scene.step([V0], [V1])
    print(len(r.contacts), r.earliest_toi, r.contacts[:5])

Names: Scene (step, advance, is_collision_free, earliest_impact, candidates), StepResult,
load_mesh, save_mesh, make_scene, run (the `mccd run` command), RunResult, Error,
CONTACT_DTYPE, RUN_STEP_DTYPE, VERTEX_FACE, EDGE_EDGE, simd_level, __version__.

What is copied and what is not:
  - Scene(meshes) copies V and F into the scene (V: any real dtype; F: any integer dtype).
  - step(), advance() and the queries read float64 and float32 position arrays in place when
    their strides are positive multiples of the item size (C order, Fortran order, slices such
    as X[:, :3]) and the data is aligned in native byte order; other dtypes, strides and
    Python lists are converted once to C-ordered float64. Each call holds every array it
    reads until it returns, so a temporary argument cannot be freed under a running step.
  - Results (StepResult.contacts, candidates(), load_mesh()'s and make_scene()'s arrays,
    RunResult.steps) are NumPy arrays over the C++ results' own memory, not copies.

Threads: steps release the GIL and run on oneTBB (all cores, or Scene(threads=N)); one scene
steps one call at a time, and a second concurrent call raises mccd.Error.
Errors: every refusal raises mccd.Error, a ValueError, with the library's message (naming the
mesh, the array and what is wrong), before any state changes.
"""
from ._mccd import (
    CONTACT_DTYPE,
    EDGE_EDGE,
    RUN_STEP_DTYPE,
    VERTEX_FACE,
    Error,
    RunResult,
    Scene,
    StepResult,
    __version__,
    load_mesh,
    make_scene,
    run,
    save_mesh,
    simd_level,
)

__all__ = [
    "CONTACT_DTYPE",
    "EDGE_EDGE",
    "RUN_STEP_DTYPE",
    "VERTEX_FACE",
    "Error",
    "RunResult",
    "Scene",
    "StepResult",
    "__version__",
    "load_mesh",
    "make_scene",
    "run",
    "save_mesh",
    "simd_level",
]
