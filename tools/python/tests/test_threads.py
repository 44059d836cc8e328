"""Threads: a step releases the GIL (another Python thread runs meanwhile), and two concurrent
steps of one scene are refused with the C++ message, while different scenes step side by side."""
import threading
import time

import numpy as np
import pytest

import mccd

REFUSAL = ("Scene: a step of this scene is already running in another thread; a scene steps one call at a "
           "time (serialise the calls, or use one Scene per thread)")


@pytest.fixture(scope="module")
def cloth():
    """A folding cloth of about 10,000 triangles: a step of a few hundred milliseconds on one thread."""
    meshes, frames = mccd.make_scene("cloth", 10, 3)
    expected = mccd.Scene(meshes).step(frames[1], frames[2]).contacts
    assert len(expected) > 1000
    return meshes, frames, expected


def test_another_python_thread_runs_during_a_step(cloth):
    meshes, frames, expected = cloth
    scene = mccd.Scene(meshes, threads=1)
    done = threading.Event()
    out = {}

    def stepper():
        t0 = time.perf_counter()
        r = scene.step(frames[1], frames[2])
        out.update(t0=t0, t1=time.perf_counter(), r=r)
        done.set()

    ticks = []
    worker = threading.Thread(target=stepper)
    worker.start()
    while not done.is_set():  # Python bytecode: runs only while this thread holds the GIL
        ticks.append(time.perf_counter())
    worker.join()
    assert np.array_equal(out["r"].contacts, expected)
    t0, t1, step = out["t0"], out["t1"], out["r"].stats["t_total"]
    assert step > 0.02, "the step is too short to tell"
    inside = [t for t in ticks if t0 < t < t1]
    gaps = np.diff([t0, *inside, t1])
    # Holding the GIL through the step would leave one gap at least as long as the C++ step.
    assert len(inside) > 100 and gaps.max() < 0.5 * step, (len(inside), gaps.max(), step)


def test_two_concurrent_steps_of_one_scene_raise(cloth):
    meshes, frames, expected = cloth
    scene = mccd.Scene(meshes, threads=1)
    refused = 0
    for attempt in range(10):  # both threads are released together; one finds the other's step running
        barrier = threading.Barrier(2)
        outcomes = [None, None]
        calls = [lambda: scene.step(frames[1], frames[2]).contacts,
                 (lambda: scene.step(frames[1], frames[2]).contacts) if attempt % 2 else
                 (lambda: scene.is_collision_free(frames[1], frames[2]))]

        def work(i):
            barrier.wait()
            try:
                outcomes[i] = calls[i]()
            except mccd.Error as e:
                outcomes[i] = e

        workers = [threading.Thread(target=work, args=(i,)) for i in range(2)]
        for w in workers:
            w.start()
        for w in workers:
            w.join()
        errors = [o for o in outcomes if isinstance(o, mccd.Error)]
        assert len(errors) <= 1, "one of the two calls must have run"
        for e in errors:
            assert str(e) == REFUSAL
        for o in outcomes:
            if isinstance(o, np.ndarray):
                assert np.array_equal(o, expected)
            elif isinstance(o, bool):
                assert o is False
        refused += len(errors)
        if refused >= 2:
            break
    assert refused >= 2, "two concurrent steps of one scene were never refused"
    # the refusals left the scene as it was
    assert np.array_equal(scene.step(frames[1], frames[2]).contacts, expected)


def test_different_scenes_step_concurrently(cloth):
    meshes, frames, expected = cloth
    scenes = [mccd.Scene(meshes, threads=1) for _ in range(2)]
    out = [None, None]
    workers = [threading.Thread(target=lambda i=i: out.__setitem__(i, scenes[i].step(frames[1], frames[2])))
               for i in range(2)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    for r in out:
        assert np.array_equal(r.contacts, expected)
