#!/usr/bin/env python3
"""The work/span prediction for a built-in scene of `mccd run` (bench_core's model, for scenes
bench_core does not hold, such as the 200K-triangle drape of issue 32).

Steps the scene three times on 1 thread with every stage's work and span measured
(SceneOptions::work_span) and keeps each stage's least work and span, as bench_core does, and
three times on 2 threads for each stage's least work there (shown beside it); then times it
`--runs` times on each thread count of `--threads` without the measurement. The
prediction for P threads is the time outside the stages (counted as serial) plus, per stage,
span + (work - span) / P. Prints one table, per step of the run (all its steps together).

Usage: perf/predict_scene.py [--scene drape] [--size 200] [--frames 10] [--threads 1 2]
Needs the Python module (cmake --install build --component python).
"""
import argparse
import statistics
import sys
import time

import mccd

STAGES = ("ws_update", "ws_refit", "ws_branch", "ws_join", "ws_input")


def run(meshes, frames, threads, work_span):
    """One run over every step of the scene: (wall seconds of all steps, summed stats)."""
    scene = mccd.Scene(meshes, threads=threads, work_span=work_span)
    wall = 0.0
    sums = {name: [0.0, 0.0] for name in STAGES}
    total = 0.0
    for positions in frames[1:]:
        start = time.perf_counter()
        result = scene.advance(positions)
        wall += time.perf_counter() - start
        stats = result.stats
        total += stats["t_total"]
        for name in STAGES:
            sums[name][0] += stats[name]["work"]
            sums[name][1] += stats[name]["span"]
    return wall, total, sums


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scene", default="drape")
    parser.add_argument("--size", type=int, default=200, help="thousands of triangles")
    parser.add_argument("--frames", type=int, default=10)
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2], help="thread counts timed")
    parser.add_argument("--runs", type=int, default=3, help="timed runs per thread count")
    parser.add_argument("--predict", type=int, nargs="+", default=[1, 2, 4, 8, 16], help="thread counts predicted")
    args = parser.parse_args()
    if args.runs < 1 or args.frames < 2 or any(t < 1 for t in args.threads + args.predict):
        sys.exit("predict_scene.py: --runs at least 1, --frames at least 2, thread counts at least 1")

    meshes, frames = mccd.make_scene(args.scene, size=args.size, frames=args.frames)
    steps = len(frames) - 1
    triangles = sum(len(f) for _, f, _ in meshes)

    def measured(threads):
        """Three measured runs on `threads`: each stage's least work and span, and the least
        time outside the stages, run by run (a run's time less its stages' work)."""
        least = {name: [float("inf"), float("inf")] for name in STAGES}
        outside = float("inf")
        for _ in range(3):
            _, total, sums = run(meshes, frames, threads, True)
            outside = min(outside, max(0.0, total - sum(w for w, _ in sums.values())))
            for name in STAGES:
                least[name][0] = min(least[name][0], sums[name][0])
                least[name][1] = min(least[name][1], sums[name][1])
        return least, outside

    least, outside = measured(1)
    # the work on 2 threads: what only several threads spend (memory moved between cores, code
    # run only there), which the 1-thread prediction does not see
    work2 = {name: w for name, (w, _) in measured(2)[0].items()}

    def predicted(p):
        return outside + sum(s + (w - s) / p for w, s in least.values())

    # the timed runs, the thread counts in turn within each round
    timed = {t: [] for t in args.threads}
    for _ in range(args.runs):
        for t in args.threads:
            timed[t].append(run(meshes, frames, t, False)[1])
    measured = {t: statistics.median(v) for t, v in timed.items()}

    ms = 1e3 / steps
    print(f"# {args.scene}, {triangles} triangles, {steps} steps; ms a step (all steps together)")
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, mccd {getattr(mccd, '__version__', '?')}")
    print("\n| stage | work | span | parallelism | work on 2 threads | 2 / 1 |\n| --- | --- | --- | --- | --- | --- |")
    for name in STAGES:
        w, s = least[name]
        ratio = f"{work2[name] / w:.2f}" if w > 0 else "n/a"
        print(f"| {name[3:]} | {w * ms:.3f} | {s * ms:.3f} | {w / s if s > 0 else float('nan'):.1f} | "
              f"{work2[name] * ms:.3f} | {ratio} |")
    print(f"| outside the stages | {outside * ms:.3f} | {outside * ms:.3f} | 1.0 | - | - |")
    print("\n| threads | predicted | measured (median) | error | measured 1 thread / predicted |")
    print("| --- | --- | --- | --- | --- |")
    one = measured.get(1)
    for p in sorted(set(args.predict) | set(args.threads)):
        pred = predicted(p) * ms
        meas = measured[p] * ms if p in measured else None
        error = f"{100 * (pred / meas - 1):+.1f}%" if meas else "(predicted only)"
        speedup = f"{one * ms / pred:.2f}x" if one else "-"
        print(f"| {p} | {pred:.2f} | {f'{meas:.2f}' if meas else 'n/a'} | {error} | {speedup} |")
    upd = sum(least[n][1] + (least[n][0] - least[n][1]) / 16 for n in ("ws_update", "ws_refit"))
    print(f"\nupdate + refit, predicted at 16 threads: {upd * ms:.3f} ms a step, "
          f"{100 * upd / predicted(16):.1f}% of the step")


if __name__ == "__main__":
    main()
