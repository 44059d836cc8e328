"""Arrays in: which are read in place (the view's data address is the array's own), which are
converted once, and that every array read stays alive while the step runs. Arrays out: the
results are arrays over the C++ results' memory."""
import gc
import sys
import threading
import weakref

import numpy as np
import pytest

import mccd
from conftest import two_triangles


def address(a: np.ndarray) -> int:
    return a.__array_interface__["data"][0]


@pytest.fixture(scope="module")
def tube():
    meshes, frames = mccd.make_scene("tube", 2, 3)
    ref = mccd.Scene(meshes).step(frames[1], frames[2])
    assert len(ref) > 0
    return meshes, frames, ref


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("order", ["C", "F"])
def test_c_and_fortran_float_arrays_are_read_in_place(tube, dtype, order):
    meshes, frames, ref = tube
    start = [np.array(f, dtype=dtype, order=order) for f in frames[1]]
    end = [np.array(f, dtype=dtype, order=order) for f in frames[2]]
    assert start[0].flags["C_CONTIGUOUS" if order == "C" else "F_CONTIGUOUS"]
    scene = mccd.Scene(meshes)
    r = scene.step(start, end)
    assert scene._last_view_data() == [(address(s), address(e)) for s, e in zip(start, end)]
    if dtype == np.float64:
        assert np.array_equal(r.contacts, ref.contacts)
    else:  # the same positions rounded to float: compare with float64 arrays of those values
        r64 = mccd.Scene(meshes).step([s.astype(np.float64) for s in start], [e.astype(np.float64) for e in end])
        assert np.array_equal(r.contacts, r64.contacts)
    # the other calls read in place too
    scene.is_collision_free(start, end)
    assert scene._last_view_data() == [(address(s), address(e)) for s, e in zip(start, end)]
    scene.advance(end)
    assert scene._last_view_data() == [(0, address(e)) for e in end]


def test_strided_slices_are_read_in_place(tube):
    meshes, frames, ref = tube
    wide = [np.hstack([f, np.ones((len(f), 2))]) for f in frames[2]]  # n x 5, read as X[:, :3]
    end = [w[:, :3] for w in wide]
    assert not end[0].flags.c_contiguous and not end[0].flags.f_contiguous
    scene = mccd.Scene(meshes)
    r = scene.step(frames[1], end)
    assert [e for _, e in scene._last_view_data()] == [address(e) for e in end]
    assert np.array_equal(r.contacts, ref.contacts)


FORMS = {
    # name: (how the positions are given, whether they are read in place)
    "float16": (lambda f: f.astype(np.float16), False),
    "big-endian": (lambda f: f.astype(">f8"), False),
    "negative row stride": (lambda f: np.ascontiguousarray(f[::-1])[::-1], False),
    "negative column stride": (lambda f: np.ascontiguousarray(f[:, ::-1])[:, ::-1], False),
    "reversed twice": (lambda f: f[::-1][::-1], True),
    "every other row": (lambda f: np.repeat(f, 2, axis=0)[::2], True),
    "list": (lambda f: f.tolist(), False),
}


@pytest.mark.parametrize("form", FORMS)
def test_other_forms_are_converted_once_with_the_same_result(tube, form):
    make, in_place = FORMS[form]
    meshes, frames, _ = tube
    start = [make(f) for f in frames[1]]
    end = [make(f) for f in frames[2]]
    expected = mccd.Scene(meshes).step([np.asarray(s, dtype=np.float64) for s in start],
                                       [np.asarray(e, dtype=np.float64) for e in end])
    scene = mccd.Scene(meshes)
    r = scene.step(start, end)
    assert np.array_equal(r.contacts, expected.contacts)
    for s, (ps, _) in zip(start, scene._last_view_data()):
        if in_place:
            assert ps == address(s)
        else:
            assert ps != 0 and (not isinstance(s, np.ndarray) or ps != address(s))


def test_integer_positions_are_converted():
    meshes, start, end = two_triangles()
    scene = mccd.Scene(meshes)
    r = scene.step([s.astype(np.int32) * 2 for s in start], [e.astype(np.int64) * 2 for e in end])
    assert np.array_equal(r.contacts, mccd.Scene(meshes).step([np.floor(s) * 2 for s in start],
                                                               [np.floor(e) * 2 for e in end]).contacts)


def test_arguments_are_held_while_the_step_runs():
    """The step is paused (by the testing hook, with the GIL released, before it reads its
    views) while another thread drops every other reference to its arguments, collects the
    garbage and fills the heap: the arguments must still be alive, and the step must read the
    right numbers. A converted argument (float16 here) may go: the step holds its float64 copy."""
    meshes, frames = mccd.make_scene("tube", 2, 3)
    expected = mccd.Scene(meshes).step(frames[1], frames[2])
    for convert in (False, True):
        scene = mccd.Scene(meshes)
        start = [f.copy() for f in frames[1]]
        end = [f.astype(np.float16).astype(np.float64) if convert else f.copy() for f in frames[2]]
        want = mccd.Scene(meshes).step(start, end) if convert else expected
        if convert:
            end = [e.astype(np.float16) for e in end]
        args = [start, end]
        refs = [weakref.ref(a) for a in start + end]
        count = len(start)
        paused, resume = threading.Event(), threading.Event()
        alive_during = []

        def hook():
            paused.set()
            resume.wait()

        scene._set_step_hook(hook)
        out = {}
        worker = threading.Thread(target=lambda: out.setdefault("r", scene.step(*args)))
        worker.start()
        assert paused.wait(60)
        for given in args:  # the very lists the step was given: now only the step holds the arrays
            given.clear()
        gc.collect()
        garbage = [np.full((len(f), 3), np.nan) for f in frames[1] + frames[2] for _ in range(4)]
        alive_during = [r() is not None for r in refs]
        resume.set()
        worker.join()
        scene._set_step_hook(None)
        # the arrays read in place are alive; a converted one may go (the step holds its copy)
        assert alive_during[:count] == [True] * count
        assert alive_during[count:] == [True] * count or convert
        assert np.array_equal(out["r"].contacts, want.contacts)
        del out, garbage
        gc.collect()
        assert all(r() is None for r in refs), "the step kept a reference after it returned"


def test_reference_counts_come_back():
    meshes, start, end = two_triangles()
    scene = mccd.Scene(meshes)
    before = [sys.getrefcount(a) for a in start + end]
    for _ in range(5):
        scene.step(start, end)
        scene.is_collision_free(start, end)
    assert [sys.getrefcount(a) for a in start + end] == before


def test_results_are_arrays_over_the_cpp_memory():
    meshes, start, end = two_triangles()
    r = mccd.Scene(meshes).step(start, end)
    c = r.contacts
    assert not c.flags.owndata and c.base is not None  # owned by the moved C++ vector
    assert c.dtype.itemsize == 48  # sizeof(mccd::Contact), fields at its offsets
    _, frames = mccd.make_scene("cloth", 1, 2)
    assert not frames[1][0].flags.owndata and frames[1][0].base is not None
    assert frames[1][0].flags.c_contiguous and frames[1][0].dtype == np.float64
