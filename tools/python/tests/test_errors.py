"""Every refusal raises mccd.Error (a ValueError) with the library's message, naming the mesh,
the array and what is wrong, before any state changes."""
import numpy as np
import pytest

import mccd
from conftest import two_triangles


def fresh():
    meshes, start, end = two_triangles()
    return mccd.Scene(meshes), meshes, start, end


def assert_unchanged(scene, meshes, end):
    """The scene steps from where it was: advance() from the meshes' V finds what a new scene finds."""
    ref = mccd.Scene(meshes).advance(end)
    r = scene.advance(end)
    assert np.array_equal(r.contacts, ref.contacts) and len(r) == 1


NAN = float("nan")


def bad_positions(start):
    """(name, start arrays, the message expected)"""
    floor, needle = start
    return [
        ("too few arrays", [floor], r"^step start: 1 position arrays for 2 meshes$"),
        ("too many arrays", [floor, needle, needle], r"^step start: 3 position arrays for 2 meshes$"),
        ("not a list", {"a": floor}, r"^step start: expected a list of n x 3 arrays"),
        ("1-D", [floor, needle.ravel()],
         r"^step start, mesh 1 \(needle\): expected an n x 3 array of float64 or float32 coordinates, got shape \(9,\) of float64$"),
        ("3-D", [floor, needle[None]],
         r"^step start, mesh 1 \(needle\): expected an n x 3 array .*, got shape \(1, 3, 3\) of float64$"),
        ("complex", [floor, needle.astype(complex)],
         r"^step start, mesh 1 \(needle\): expected .* got shape \(3, 3\) of complex128$"),
        ("bool", [floor.astype(bool), needle],
         r"^step start, mesh 0 \(floor\): expected .* got shape \(3, 3\) of bool$"),
        ("strings", [floor, needle.astype(str)], r"^step start, mesh 1 \(needle\): expected .* of <U32$"),
        ("ragged list", [floor, [[0, 0, 0], [1, 1]]], r"^step start, mesh 1 \(needle\): cannot be read as an array"),
        ("4 columns", [floor, np.hstack([needle, needle[:, :1]])],
         r"^step start, mesh 1 \(needle\): has 4 columns, expected 3 \(x, y, z\)$"),
        ("rows", [floor, needle[:2]], r"^step start, mesh 1 \(needle\): has 2 vertices, expected 3$"),
        ("NaN", [floor, np.where(np.arange(9).reshape(3, 3) == 5, NAN, needle)],
         r"^step start, mesh 1 \(needle\): vertex 1: coordinate z is not finite \(nan\)$"),
        ("inf in float32", [np.where(floor == 1, np.float32(np.inf), floor.astype(np.float32)), needle],
         r"^step start, mesh 0 \(floor\): vertex 1: coordinate x is not finite \(inf\)$"),
        ("static: none given for a moving mesh", [floor, None], r"^step start, mesh 1 \(needle\): has 0 vertices, expected 3$"),
    ]


@pytest.mark.parametrize("case", range(14))
def test_bad_positions_raise_before_any_change(case):
    scene, meshes, start, end = fresh()
    name, bad, message = bad_positions(start)[case]
    for call in (lambda: scene.step(bad, end), lambda: scene.is_collision_free(bad, end),
                 lambda: scene.earliest_impact(bad, end), lambda: scene.candidates(bad, end)):
        with pytest.raises(mccd.Error, match=message.replace("step start", "(step|query) start")) as info:
            call()
        assert isinstance(info.value, ValueError), name
    if not isinstance(bad, dict):
        with pytest.raises(mccd.Error, match=message.replace("step start", "advance")):
            scene.advance(bad)
    assert_unchanged(scene, meshes, end)


def test_a_bad_end_raises_too():
    scene, meshes, start, end = fresh()
    with pytest.raises(mccd.Error, match=r"^step end, mesh 0 \(floor\): has 2 vertices, expected 3$"):
        scene.step(start, [end[0][:2], end[1]])
    assert_unchanged(scene, meshes, end)


def test_bad_method_names():
    scene, meshes, start, end = fresh()
    with pytest.raises(mccd.Error, match="fbd"):  # the message names the accepted values
        scene.step(start, end, method="fastest")
    with pytest.raises(mccd.Error, match="fbd"):
        mccd.Scene(meshes, method="fastest")
    assert_unchanged(scene, meshes, end)


def mesh_cases():
    V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    F = np.array([[0, 1, 2], [1, 3, 2]])
    return [
        ("index out of range", (V, np.array([[0, 1, 2], [1, 4, 2]]), "sheet"),
         r"^sheet: face 1: vertex index 4 out of range \[0, 4\)$"),
        ("negative index", (V, np.array([[0, 1, 2], [1, -1, 2]]), "sheet"),
         r"^sheet: face 1: vertex index -1 out of range \[0, 4\)$"),
        ("index beyond 32 bits", (V, np.array([[0, 1, 2], [1, 2**32, 2]], dtype=np.uint64)),
         r"^mesh 0: face 1: vertex index 4294967296 out of range \[0, 4\)$"),
        ("repeated index", (V, np.array([[0, 1, 1]])), r"^mesh 0: face 0: repeated vertex index \(0, 1, 1\)$"),
        ("float faces", (V, F.astype(float)),
         r"^mesh 0: F: expected an m x 3 integer array of vertex indices, got shape \(2, 3\) of float64$"),
        ("faces of 4", (V, np.array([[0, 1, 3, 2]])),
         r"^mesh 0: F: expected an m x 3 integer array of vertex indices, got shape \(1, 4\) of int64$"),
        ("V of 2 columns", (V[:, :2], F),
         r"^mesh 0: V: expected an n x 3 array of coordinates, got shape \(4, 2\) of float64$"),
        ("V complex", (V.astype(complex), F), r"^mesh 0: V: expected an n x 3 array .* of complex128$"),
        ("V NaN", (np.where(V == 1, NAN, V), F), r"^mesh 0: vertex 1: coordinate x is not finite \(nan\)$"),
        ("not a tuple", V, r"^mesh 0: expected a \(V, F\) or \(V, F, name\) tuple, got ndarray$"),
        ("one item", (V,), r"^mesh 0: expected a \(V, F\) or \(V, F, name\) tuple, got 1 items$"),
        ("name not a str", (V, F, 7), r"^mesh 0: the name \(third item\) must be a str$"),
    ]


@pytest.mark.parametrize("case", range(12))
def test_bad_meshes(case):
    name, mesh, message = mesh_cases()[case]
    with pytest.raises(mccd.Error, match=message):
        mccd.Scene([mesh])


def test_bad_options():
    meshes, start, end = two_triangles()
    cases = [
        (dict(threads=0), r"^threads: 0: expected 1 to 1024 \(or None\)$"),
        (dict(min_distance=-1.0), "min_distance"),
        (dict(min_distance=NAN), "min_distance"),
        (dict(static=[True]), r"^static: 1 values for 2 meshes$"),
        (dict(static=[0, 1]), r"^static: mesh 0: expected a bool, got int$"),
        (dict(self_collision="yes"), r"^self_collision: expected a bool or one bool per mesh$"),
        (dict(volume="sphere"), "kdop18"),
        (dict(bvh="octree"), "median"),
        (dict(representatives="some"), "canonical"),
        (dict(leaf_size=40), "leaf"),
    ]
    for kwargs, message in cases:
        with pytest.raises(mccd.Error, match=message):
            mccd.Scene(meshes, **kwargs)
    with pytest.raises(mccd.Error, match=r"^meshes: expected a list of \(V, F\) tuples$"):
        mccd.Scene("cloth.ply")
    # numpy bools are bools
    assert len(mccd.Scene(meshes, static=np.array([True, False])).step([None, start[1]], [None, end[1]])) == 1


def test_file_errors_name_the_file(tmp_path):
    bad = tmp_path / "bad.ply"
    bad.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0\n")
    with pytest.raises(mccd.Error, match="bad.ply"):
        mccd.load_mesh(bad)
    with pytest.raises(mccd.Error, match="unsupported|extension|.txt"):
        mccd.load_mesh(tmp_path / "mesh.txt")
