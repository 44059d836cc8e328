#pragma once
/// @file The sweep over methods and thread counts for one workload. The reference is the
/// serial result (traverse, one thread); every variant first runs once as a warm-up whose
/// contacts are compared with the reference at every step, and only then is timed; the timed
/// runs of a method alternate between the thread counts.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <mccd/core/options.h>
#include <mccd/core/stats.h>

#include "harness/workload.h"

namespace mccd::bench {

/// One run of a workload from a fresh scene: its statistics added over all its steps.
struct RunRecord {
  std::string scene;
  /// "default" (the library's defaults); "paper": the paper's configuration (its median BVH,
  /// one triangle per leaf, the canonical rule with its orphan set), run for figures 7 and 9;
  /// "work-span" and "work-span-2": the defaults with the stages' work and span measured, on 1
  /// and on 2 threads (SweepOptions::work_span_runs).
  std::string config = "default";
  Method method = Method::Fbd;
  int threads = 1;
  int run = 0;  ///< 0: the warm-up (which checked the contacts); 1..repeats: timed
  int steps = 0, intervals = 0;
  double wall_ms = 0;        ///< wall-clock time of all steps (Scene::advance calls)
  double first_step_ms = 0;  ///< of the first step (where fbd builds its front)
  /// Work-span records: the least, over their runs, of a run's wall time less the work of its
  /// stages (ms; what the prediction counts as serial). Negative: not measured.
  double outside_ms = -1;
  StepStats sum;             ///< counts and stage times (seconds) over all steps
  std::uint64_t contacts = 0;
  /// Over the steps that built the front from the root (fbd): how many, the front nodes
  /// after them, and the adjacent leaf pairs that the orphan set kept out of the front.
  std::uint64_t rebuilds = 0, rebuild_front = 0, rebuild_adjacent = 0;
  std::uint64_t max_front_bytes = 0, max_front_size = 0;
};

struct SweepOptions {
  std::vector<Method> methods{Method::Traverse, Method::Phc, Method::Fbd};
  std::vector<int> threads{1, 2};
  int repeats = 3;                                     ///< timed runs per variant
  /// Also runs traverse and fbd once each on 1 thread in the paper's configuration (checked
  /// against the reference like every warm-up): the volume tests its front saves and the
  /// front length its orphan set saves (figures 7 and 9).
  bool paper_runs = true;
  /// Also runs each method three times on 1 thread with its stages' work and span measured
  /// (SceneOptions::work_span; config "work-span", checked against the reference; each
  /// stage's least work and span of the three kept, as one record), from which the report
  /// predicts every thread count (predicted_ms); and, when `threads` holds more than 1, three
  /// times on 2 threads the same way (config "work-span-2"), whose work the report shows beside.
  bool work_span_runs = true;
  std::function<void(const std::string&)> progress;    ///< one line per run, may be empty
};

/// Runs the sweep on `w`. Throws mccd::Error naming the scene, method, thread count and step
/// when a variant's contacts differ from the reference.
std::vector<RunRecord> sweep_workload(const Workload& w, const SweepOptions& options);

}  // namespace mccd::bench
