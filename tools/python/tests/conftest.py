"""Shared fixtures of the Python tests (run by CTest through pytest, PYTHONPATH=build/python)."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import mccd

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[3]


def data_dir() -> pathlib.Path:
    """$MCCD_DATA_DIR, else the shared data beside the checkout (as the C++ tests)."""
    env = os.environ.get("MCCD_DATA_DIR") or os.environ.get("MCCD_TEST_DEFAULT_DATA_DIR")
    return pathlib.Path(env) if env else SOURCE_DIR.parent / "shared" / "data"


def require(path: pathlib.Path) -> pathlib.Path:
    if not path.exists():
        pytest.skip(f"shared data not found at {path} (set MCCD_DATA_DIR to run this)")
    return path


@pytest.fixture(scope="session")
def cloth_ball_frames() -> pathlib.Path:
    return require(data_dir() / "toi" / "cloth-ball" / "frames")


@pytest.fixture(scope="session")
def cloth_ball(cloth_ball_frames):
    """(V0, F, V1): the real cloth-ball step 92 -> 93."""
    V0, F = mccd.load_mesh(cloth_ball_frames / "cloth_ball92.ply")
    V1, F1 = mccd.load_mesh(cloth_ball_frames / "cloth_ball93.ply")
    assert np.array_equal(F, F1)
    return V0, F, V1


@pytest.fixture(scope="session")
def cli() -> pathlib.Path:
    """The `mccd` command-line tool of the same build (CTest sets MCCD_CLI)."""
    path = os.environ.get("MCCD_CLI")
    if not path:
        path = SOURCE_DIR / "build" / "bin" / "mccd"
    path = pathlib.Path(path)
    if not path.exists():
        pytest.fail(f"the mccd command-line tool is needed to compare with C++: {path} does not exist "
                    "(build the mccd_cli target, or set MCCD_CLI)")
    return path


def run_cli(cli, *args) -> subprocess.CompletedProcess:
    r = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True)
    assert r.returncode in (0, 1), f"mccd {' '.join(map(str, args))} failed ({r.returncode}): {r.stderr}"
    return r


CSV_DTYPE = np.dtype([("frame", "u8"), ("substep", "u8"), ("kind", "U2"), ("mesh_a", "u4"), ("a", "u4"),
                      ("mesh_b", "u4"), ("b", "u4"), ("v0", "u4"), ("v1", "u4"), ("v2", "u4"), ("v3", "u4"),
                      ("toi", "f8"), ("t", "f8")])


def read_contacts_csv(path) -> np.ndarray:
    """A contacts CSV of `mccd run` as a structured array (toi and t read back exactly: %.17g)."""
    lines = pathlib.Path(path).read_text().splitlines()
    assert lines[0] == "frame,substep,kind,mesh_a,feature_a,mesh_b,feature_b,v0,v1,v2,v3,toi,t", lines[0]
    assert not any(line.startswith("#") for line in lines), "the run did not complete"
    rows = [tuple(line.split(",")) for line in lines[1:]]
    out = np.empty(len(rows), CSV_DTYPE)
    for name, column in zip(CSV_DTYPE.names, zip(*rows) if rows else [()] * len(CSV_DTYPE.names)):
        out[name] = np.array(column, dtype=CSV_DTYPE[name]) if rows else []
    return out


def contacts_as_csv_rows(contacts: np.ndarray, frame: int) -> np.ndarray:
    """Python contacts laid out as read_contacts_csv's rows of one frame (one sub-step)."""
    out = np.empty(len(contacts), CSV_DTYPE)
    out["frame"] = frame
    out["substep"] = 0
    out["kind"] = np.where(contacts["kind"] == mccd.VERTEX_FACE, "vf", "ee")
    for f in ("mesh_a", "a", "mesh_b", "b"):
        out[f] = contacts[f]
    for k in range(4):
        out[f"v{k}"] = contacts["vertices"][:, k]
    out["t"] = contacts["toi"]
    out["toi"] = frame + contacts["toi"]  # frame time, computed as `mccd run` does (one sub-step)
    return out


def two_triangles():
    """Two single-triangle meshes: mesh 1's first vertex passes down through mesh 0's face at
    t = 0.5 (mesh 0 at rest). Returns (meshes, start, end)."""
    VA = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    FA = np.array([[0, 1, 2]])
    VB0 = np.array([[0.2, 0.2, 1.0], [0.2, 0.2, 3.0], [0.4, 0.2, 3.0]])
    VB1 = VB0 - [0.0, 0.0, 2.0]
    FB = np.array([[0, 1, 2]])
    return [(VA, FA, "floor"), (VB0, FB, "needle")], [VA, VB0], [VA, VB1]
