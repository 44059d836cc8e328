#!/usr/bin/env python3
"""A cloth-ball step through Python against the same step through C++, side by side.

Each round times one step both ways on the same scene and the same arrays, in alternating
order (Python first in even rounds, C++ first in odd ones):
  - Python: `r = scene.step([V0], [V1]); del r` timed with time.perf_counter() around the call
    (argument checks, the views, the GIL released and taken back, the step, the contacts
    array and the stats dict, and dropping the result);
  - C++: `scene._time_cpp_step([V0], [V1])`, the same Scene::step timed inside C++ with
    std::chrono::steady_clock (its views made before the clock starts, the result destroyed
    before it stops).
Both also record the calling thread's CPU time (time.thread_time(), CLOCK_THREAD_CPUTIME_ID):
with --threads 1 the whole step runs on that thread, and its CPU time is far less disturbed
than the wall time by other work on a busy machine.
Two regimes: `kept` steps one scene again and again (the front kept from the last step, as a
simulation does), `fresh` builds a new scene for every timed step (the front built from the
root, as `bench_step` and `mccd toi-check` do). Prints the medians, their ratio, the median of
the rounds' differences (Python minus C++, each round's two steps timed back to back), and
`uptime`; then the fixed cost of a call on a scene of two triangles (a step of microseconds).

    PYTHONPATH=build/python /usr/bin/python3 tools/python/bench/bench_step.py [--rounds 21] [--threads N]
"""
import argparse
import os
import pathlib
import statistics
import subprocess
import time

import numpy as np

import mccd

here = pathlib.Path(__file__).resolve()
default_data = os.environ.get("MCCD_DATA_DIR") or str(here.parents[3].parent / "shared" / "data")
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--data", default=default_data, help="the shared data folder (default: %(default)s)")
parser.add_argument("--rounds", type=int, default=21, help="timed rounds per regime (default: %(default)s)")
parser.add_argument("--threads", type=int, default=None, help="the scene's arena (default: the caller's, every core)")
args = parser.parse_args()

frames = pathlib.Path(args.data) / "toi" / "cloth-ball" / "frames"
V0, F = mccd.load_mesh(frames / "cloth_ball92.ply")
V1, _ = mccd.load_mesh(frames / "cloth_ball93.ply")
start, end = [V0], [V1]


def python_step(scene, s=start, e=end):
    t0, c0 = time.perf_counter(), time.thread_time()
    r = scene.step(s, e)
    n = len(r)
    del r
    return time.perf_counter() - t0, time.thread_time() - c0, n


def cpp_step(scene, s=start, e=end):
    return scene._time_cpp_step(s, e)


def measure(regime):
    scene = mccd.Scene([(V0, F)], threads=args.threads)
    python_step(scene), cpp_step(scene)  # warm up: memory, the front, the thread pool
    wall = {"python": [], "c++": []}
    cpu = {"python": [], "c++": []}
    for k in range(args.rounds):
        order = [("python", python_step), ("c++", cpp_step)]
        if k % 2:
            order.reverse()
        for name, fn in order:
            if regime == "fresh":
                scene = mccd.Scene([(V0, F)], threads=args.threads)
            seconds, cpu_seconds, n = fn(scene)
            assert n == 113854, n
            wall[name].append(seconds)
            cpu[name].append(cpu_seconds)
    return wall, cpu


def line(label, t):
    py, cpp = statistics.median(t["python"]), statistics.median(t["c++"])
    diff = statistics.median(p - c for p, c in zip(t["python"], t["c++"]))
    return (f"{label:16s} python median {1e3 * py:7.1f} ms  c++ median {1e3 * cpp:7.1f} ms  "
            f"python / c++ = {py / cpp:.3f}  median difference {1e3 * diff:+.2f} ms  "
            f"(min {1e3 * min(t['python']):.1f} / {1e3 * min(t['c++']):.1f} ms)")


def tiny_overhead(calls=2000):
    """Median seconds of a Python step and of the same step timed in C++, two triangles."""
    VA = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    VB0 = np.array([[0.2, 0.2, 1.0], [0.2, 0.2, 3.0], [0.4, 0.2, 3.0]])
    VB1 = VB0 - [0.0, 0.0, 2.0]
    T = np.array([[0, 1, 2]])
    scene = mccd.Scene([(VA, T), (VB0, T)], threads=args.threads)
    s, e = [VA, VB0], [VA, VB1]
    py, cpp = [], []
    for _ in range(calls):
        py.append(python_step(scene, s, e)[0])
        cpp.append(cpp_step(scene, s, e)[0])
    return statistics.median(py), statistics.median(cpp)


print(f"mccd {mccd.__version__} ({mccd.simd_level}), cloth-ball 92 -> 93 (92,230 triangles, 113,854 contacts), "
      f"threads {args.threads or 'default (every core)'}, {args.rounds} rounds per regime, alternating")
print("uptime before:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
for regime in ("kept", "fresh"):
    wall, cpu = measure(regime)
    print(line(f"{regime} wall", wall))
    print(line(f"{regime} thread CPU", cpu))
py, cpp = tiny_overhead()
print(f"two triangles: python median {1e6 * py:.1f} us, c++ median {1e6 * cpp:.1f} us: "
      f"{1e6 * (py - cpp):.1f} us per call in Python")
print("uptime after: ", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
