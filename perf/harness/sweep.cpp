#include "harness/sweep.h"

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/error.h>

namespace mccd::bench {

namespace {

using Contacts = std::vector<std::vector<Contact>>;

// One run from a fresh scene. With `keep`, the contacts of every step are stored; with
// `check`, they are compared with it.
RunRecord run_once(const Workload& w, Method method, int threads, Contacts* keep, const Contacts* check,
                   SceneOptions opt = {}) {
  tbb::task_arena arena(threads);
  opt.arena = &arena;
  opt.method = method;
  TriMesh mesh = w.mesh;
  mesh.vertices = w.positions[0];
  Scene scene({std::move(mesh)}, opt);
  RunRecord rec;
  rec.scene = w.name;
  rec.method = method;
  rec.threads = threads;
  rec.steps = int(w.steps());
  rec.intervals = w.intervals;
  StepResult r;  // kept from step to step, as a simulator stepping every frame keeps it
  for (std::size_t k = 1; k < w.positions.size(); ++k) {
    const auto start = std::chrono::steady_clock::now();
    scene.advance(w.positions[k], r, method);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (check && r.contacts != (*check)[k - 1]) {
      char msg[256];
      std::snprintf(msg, sizeof msg, "%s: %s with %d threads: step %zu: %zu contacts differ from the serial result (%zu)",
                    w.name.c_str(), to_string(method), threads, k, r.contacts.size(), (*check)[k - 1].size());
      throw Error(msg);
    }
    rec.wall_ms += ms;
    if (k == 1) rec.first_step_ms = ms;
    rec.sum += r.stats;
    rec.contacts += r.contacts.size();
    if (r.stats.rebuilds) {
      rec.rebuilds += r.stats.rebuilds;
      rec.rebuild_front += r.stats.front_size;
      rec.rebuild_adjacent += r.stats.adjacent_leaf_pairs;
    }
    rec.max_front_bytes = std::max(rec.max_front_bytes, r.stats.front_bytes);
    rec.max_front_size = std::max(rec.max_front_size, r.stats.front_size);
    if (keep) keep->push_back(r.contacts);
  }
  return rec;
}

}  // namespace

std::vector<RunRecord> sweep_workload(const Workload& w, const SweepOptions& options) {
  if (w.steps() == 0) throw Error(w.name + ": no step to run");
  Contacts reference;
  run_once(w, Method::Traverse, 1, &reference, nullptr);
  std::vector<RunRecord> out;
  auto record = [&](Method m, int threads, int run) {
    RunRecord rec = run_once(w, m, threads, nullptr, run == 0 ? &reference : nullptr);
    rec.run = run;
    if (options.progress) {
      char line[200];
      std::snprintf(line, sizeof line, "%-20s %-8s %2d threads  %-17s %9.2f ms per frame", w.name.c_str(), to_string(m),
                    threads, run == 0 ? "warm-up, checked" : ("run " + std::to_string(run)).c_str(),
                    rec.wall_ms / rec.intervals);
      options.progress(line);
    }
    out.push_back(std::move(rec));
  };
  // the timed runs of the thread counts alternate, so a change in the machine's load while a
  // method is timed falls on every thread count alike
  for (Method m : options.methods) {
    for (int threads : options.threads) record(m, threads, 0);
    for (int run = 1; run <= options.repeats; ++run)
      for (int threads : options.threads) record(m, threads, run);
  }
  // One checked run in another configuration, labelled.
  auto configured = [&](Method m, int threads, const SceneOptions& opt, const char* config, const char* label) {
    RunRecord rec = run_once(w, m, threads, nullptr, &reference, opt);
    rec.config = config;
    if (options.progress) {
      char line[200];
      std::snprintf(line, sizeof line, "%-20s %-8s %2d thread%s  %-17s %9.2f ms per frame", w.name.c_str(),
                    to_string(m), threads, threads == 1 ? " " : "s", label, rec.wall_ms / rec.intervals);
      options.progress(line);
    }
    out.push_back(std::move(rec));
  };
  if (options.work_span_runs) {
    // Three measured runs; each stage's least work and span of the three (a stall of a shared
    // machine only adds to a task, and one stalled task would be taken for the span). On 1
    // thread for the prediction; on 2 as well when the sweep runs several threads, for the
    // work that only several threads spend (RunRecord::config "work-span-2").
    SceneOptions measured;
    measured.work_span = true;
    const bool several = std::any_of(options.threads.begin(), options.threads.end(), [](int t) { return t > 1; });
    for (Method m : options.methods) {
      for (int threads : {1, 2}) {
        if (threads == 2 && !several) continue;
        configured(m, threads, measured, threads == 1 ? "work-span" : "work-span-2", "work and span");
        RunRecord& best = out.back();
        // The time outside the stages is taken run by run (the least stages of different runs
        // added up are less than any run's: their difference is noise, not serial time).
        auto outside = [](const RunRecord& r) { return std::max(0.0, r.wall_ms - 1e3 * r.sum.staged_work()); };
        best.outside_ms = outside(best);
        for (int k = 1; k < 3; ++k) {
          const RunRecord r = run_once(w, m, threads, nullptr, &reference, measured);
          auto least = [](WorkSpan& a, const WorkSpan& b) {
            a.work = std::min(a.work, b.work);
            a.span = std::min(a.span, b.span);
          };
          least(best.sum.ws_update, r.sum.ws_update);
          least(best.sum.ws_refit, r.sum.ws_refit);
          least(best.sum.ws_search, r.sum.ws_search);
          least(best.sum.ws_self, r.sum.ws_self);
          least(best.sum.ws_branch, r.sum.ws_branch);
          least(best.sum.ws_join, r.sum.ws_join);
          least(best.sum.ws_input, r.sum.ws_input);
          best.wall_ms = std::min(best.wall_ms, r.wall_ms);
          best.outside_ms = std::min(best.outside_ms, outside(r));
        }
      }
    }
  }
  if (options.paper_runs) {
    SceneOptions paper;
    paper.bvh = BvhBuild::Median;
    paper.leaf_size = 1;
    paper.representatives = Representatives::Canonical;
    for (Method m : {Method::Traverse, Method::Fbd}) configured(m, 1, paper, "paper", "paper's setting");
  }
  return out;
}

}  // namespace mccd::bench
