"""The module's API on small scenes: results, options, files, docstrings and stubs."""
import ast
import math
import pathlib
import re

import numpy as np
import pytest

import mccd
from conftest import SOURCE_DIR, two_triangles

METHODS = ["bruteforce", "traverse", "phc", "fbd"]


def test_version_and_error_type():
    project = re.search(r"project\(mccd VERSION ([0-9.]+)", (SOURCE_DIR / "CMakeLists.txt").read_text()).group(1)
    assert mccd.__version__ == project
    assert issubclass(mccd.Error, ValueError)
    assert mccd.simd_level in ("scalar", "sse2", "avx2", "avx512")


def test_one_vertex_through_a_face():
    meshes, start, end = two_triangles()
    scene = mccd.Scene(meshes)
    r = scene.step(start, end)
    assert isinstance(r, mccd.StepResult)
    assert len(r) == 1 and r.contacts.dtype == mccd.CONTACT_DTYPE
    c = r.contacts[0]
    assert c["kind"] == mccd.VERTEX_FACE
    assert (c["mesh_a"], c["a"], c["mesh_b"], c["b"]) == (1, 0, 0, 0)
    assert list(c["vertices"]) == [0, 0, 1, 2]  # the vertex, then the face's three
    assert 0.5 - 1e-6 <= c["toi"] <= 0.5  # conservative: never late
    assert r.earliest_toi == c["toi"]
    assert r.stats["vf_contacts"] == 1 and r.stats["ee_contacts"] == 0
    assert r.stats["method"] == "fbd" and r.stats["t_total"] > 0
    assert "1 contacts (1 vertex-face, 0 edge-edge)" in repr(r)


def test_no_contact_reports_inf():
    meshes, start, _ = two_triangles()
    scene = mccd.Scene(meshes)
    r = scene.step(start, start)
    assert len(r) == 0 and math.isinf(r.earliest_toi)
    assert scene.is_collision_free(start, start)
    assert math.isinf(scene.earliest_impact(start, start))


def test_advance_starts_from_the_last_end():
    meshes, start, end = two_triangles()
    scene = mccd.Scene(meshes)
    assert len(scene.advance(end)) == 1  # from the meshes' own V, which are `start`
    assert len(scene.advance(end)) == 0  # at rest
    r = scene.advance(start)  # back up through the face
    assert len(r) == 1 and 0.5 - 1e-6 <= r.earliest_toi <= 0.5


def test_queries_leave_the_scene_as_it_was():
    meshes, start, end = two_triangles()
    scene = mccd.Scene(meshes)
    scene.advance(end)
    assert not scene.is_collision_free(start, end)
    assert scene.earliest_impact(start, end) == scene.step(start, end).earliest_toi
    cands = scene.candidates(start, end)
    assert cands.dtype == mccd.CONTACT_DTYPE and len(cands) >= 1
    assert set(cands["toi"]) <= {0.0, 0.25, 0.5, 0.75}
    # step() moved the last end to `end`; the queries before it did not move it either
    assert len(scene.advance(end)) == 0


def test_all_methods_agree_on_a_generated_scene():
    meshes, frames = mccd.make_scene("cloth", 1, 4)
    results = {}
    for method in METHODS:
        scene = mccd.Scene(meshes, method=method)
        assert scene.method == method
        results[method] = [scene.advance(f).contacts for f in frames[1:]]
    assert sum(len(c) for c in results["fbd"]) > 0
    for method in METHODS[:-1]:
        for a, b in zip(results[method], results["fbd"]):
            assert np.array_equal(a, b), method
    # and per call
    scene = mccd.Scene(meshes)
    r = scene.step(frames[1], frames[2], method="bruteforce")
    assert r.stats["method"] == "bruteforce" and np.array_equal(r.contacts, results["fbd"][1])


def test_contacts_sorted_and_vertices_filled():
    meshes, frames = mccd.make_scene("spheres", 2, 3)
    scene = mccd.Scene(meshes)
    c = scene.step(frames[0], frames[1]).contacts
    assert len(c) > 0 and set(np.unique(c["kind"])) <= {0, 1}
    key = list(zip(c["kind"], c["mesh_a"], c["a"], c["mesh_b"], c["b"]))
    assert key == sorted(key) and len(set(key)) == len(key)
    faces = [scene.mesh(i)[1] for i in range(scene.num_meshes)]
    vf = c[c["kind"] == mccd.VERTEX_FACE]
    for rec in vf[:50]:
        assert rec["vertices"][0] == rec["a"]
        assert list(rec["vertices"][1:]) == list(faces[rec["mesh_b"]][rec["b"]])
    ee = c[c["kind"] == mccd.EDGE_EDGE]
    assert np.all(ee["vertices"][:, 0] < ee["vertices"][:, 1]) and np.all(ee["vertices"][:, 2] < ee["vertices"][:, 3])


def test_static_and_self_collision_options():
    meshes, start, end = two_triangles()
    scene = mccd.Scene(meshes, static=[True, False])
    assert len(scene.step([None, start[1]], [None, end[1]])) == 1
    assert len(scene.step(start, end)) == 1  # its own unchanged positions are accepted too
    moved = start[0] + [0.0, 0.0, 0.1]
    with pytest.raises(mccd.Error, match="the mesh is static"):
        scene.step([moved, start[1]], end)
    # self_collision: a folding cloth touches itself; without self-collision it cannot
    meshes, frames = mccd.make_scene("cloth", 1, 4)
    assert len(mccd.Scene(meshes).step(frames[2], frames[3])) > 0
    assert len(mccd.Scene(meshes, self_collision=False).step(frames[2], frames[3])) == 0
    assert len(mccd.Scene(meshes, self_collision=[False]).step(frames[2], frames[3])) == 0


def test_min_distance_reports_near_pairs():
    meshes, start, _ = two_triangles()
    lifted = [start[0], start[1] + [0.0, 0.0, -0.95]]  # the needle's tip 0.05 above the floor, at rest
    assert len(mccd.Scene(meshes).step(lifted, lifted)) == 0
    assert len(mccd.Scene(meshes, min_distance=0.1).step(lifted, lifted)) >= 1


def test_threads_option_gives_the_same_contacts():
    meshes, frames = mccd.make_scene("tube", 2, 4)
    ref = [mccd.Scene(meshes, threads=1).step(frames[k], frames[k + 1]).contacts for k in range(3)]
    assert sum(map(len, ref)) > 0
    for threads in (2, 3):
        scene = mccd.Scene(meshes, threads=threads)
        assert scene.threads == threads
        for k in range(3):
            assert np.array_equal(scene.step(frames[k], frames[k + 1]).contacts, ref[k])
    assert mccd.Scene(meshes).threads is None


def test_load_and_save_mesh(tmp_path):
    meshes, _ = mccd.make_scene("spheres", 1, 2)
    V, F, _name = meshes[0]
    for ext in ("ply", "obj"):
        path = tmp_path / f"m.{ext}"
        mccd.save_mesh(path, V, F)
        V2, F2 = mccd.load_mesh(path)
        assert V2.dtype == np.float64 and F2.dtype == np.uint32
        assert np.array_equal(V2, V) and np.array_equal(F2, F)
        assert V2.flags.writeable and V2.base is not None  # an array over the reader's own vector
    with pytest.raises(mccd.Error, match="nothing.ply"):
        mccd.load_mesh(tmp_path / "nothing.ply")
    with pytest.raises(mccd.Error, match="expected a .ply or .obj"):
        mccd.save_mesh(tmp_path / "m.stl", V, F)


def test_scene_mesh_views_are_read_only_and_keep_the_scene():
    meshes, _, _ = two_triangles()
    scene = mccd.Scene(meshes)
    V, F, name = scene.mesh(1)
    assert name == "needle" and np.array_equal(V, meshes[1][0]) and np.array_equal(F, meshes[1][1])
    assert not V.flags.writeable and not F.flags.writeable
    del scene
    assert V.sum() == meshes[1][0].sum()  # still valid: the view keeps the scene alive
    with pytest.raises(mccd.Error, match="the scene has 2 meshes"):
        mccd.Scene(meshes).mesh(2)


def test_make_scene_matches_scene_sizes():
    meshes, frames = mccd.make_scene("drape", 2, 5)
    assert len(frames) == 5 and len(meshes) == 2
    for V, F, name in meshes:
        assert V.shape[1] == 3 and F.shape[1] == 3 and isinstance(name, str)
    for frame in frames:
        assert [f.shape for f in frame] == [m[0].shape for m in meshes]
    assert np.array_equal(frames[0][0], meshes[0][0])
    with pytest.raises(mccd.Error, match="unknown|scene"):
        mccd.make_scene("teapot", 1, 2)
    with pytest.raises(mccd.Error, match="at most 20000"):
        mccd.make_scene("cloth", 200, 200)


def test_docstrings_cover_the_public_names():
    for name in mccd.__all__:
        obj = getattr(mccd, name)
        if callable(obj):
            assert obj.__doc__ and len(obj.__doc__) > 40, name
    for method in ("step", "advance", "is_collision_free", "earliest_impact", "candidates", "mesh"):
        doc = getattr(mccd.Scene, method).__doc__
        assert doc and len(doc) > 80, method
    text = mccd.Scene.__doc__
    for word in ("meshes", "threads", "static", "self_collision", "copied"):
        assert word in text
    assert "in place" in mccd.Scene.step.__doc__ and "converted" in mccd.Scene.step.__doc__
    assert "in place" in mccd.__doc__ and "copies" in mccd.__doc__


def test_stubs_declare_every_public_name():
    stub = pathlib.Path(mccd.__file__).with_suffix(".pyi")
    assert stub.exists() and (stub.parent / "py.typed").exists()
    tree = ast.parse(stub.read_text())
    declared = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            declared.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            declared.add(node.target.id)
    assert set(mccd.__all__) <= declared, set(mccd.__all__) - declared
    scene_stub = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Scene")
    members = {n.name for n in scene_stub.body if isinstance(n, ast.FunctionDef)}
    public = {n for n in dir(mccd.Scene) if not n.startswith("__")}
    assert public <= members, public - members


def test_stats_carry_every_counter_and_the_work_and_span_when_asked():
    meshes, frames = mccd.make_scene("cloth", 2, 3)
    plain = mccd.Scene(meshes).step(frames[1], frames[2])
    measured = mccd.Scene(meshes, work_span=True).step(frames[1], frames[2])
    assert np.array_equal(plain.contacts, measured.contacts)
    for key in ("t_update", "t_refit", "t_front", "t_self", "t_contacts", "t_total", "front_size", "leaf_pairs"):
        assert key in plain.stats
    assert plain.stats["vf_contacts"] + plain.stats["ee_contacts"] == len(plain)
    assert set(plain.stats["vf_ccd"]) >= {"queries", "hits", "fallbacks"}
    stages = ("ws_update", "ws_refit", "ws_search", "ws_self", "ws_branch", "ws_join", "ws_input")
    assert all(plain.stats[s] == {"work": 0.0, "span": 0.0} for s in stages)
    assert measured.stats["ws_search"]["work"] > 0
    assert all(0 <= measured.stats[s]["span"] <= measured.stats[s]["work"] + 1e-9 for s in stages)
