#pragma once
/// @file From runs to figures: the median and spread of each variant, the serial fraction of
/// each stage under Amdahl's law, and the per-scene counts the paper's figures plot.
///
/// Serial fraction. Amdahl's law models the time on p threads as T(p) = T(1) (s + (1 - s) / p).
/// With r_p = T(p) / T(1), r_p - 1/p = s (1 - 1/p) is linear in s; the least-squares fit over
/// the measured thread counts p > 1 is
///     s = sum_p (r_p - 1/p)(1 - 1/p) / sum_p (1 - 1/p)^2,
/// which for 1 and 2 threads only is s = 2 T(2) / T(1) - 1. It is clamped to [0, 1]. The
/// modelled speedup on n threads is then 1 / (s + (1 - s) / n).
#include <array>
#include <string>
#include <vector>

#include "harness/sweep.h"

namespace mccd::bench {

/// The stages of a step as StepStats times them, and the whole step (wall clock). The search
/// and the self stage ("self") run beside each other in the step's flow graph, sharing the
/// threads, so neither one's time alone says how it scales: kSearchAndSelf is the part of the
/// step they take together (the step's engine time less the update, the refit and the join),
/// the one whose serial fraction means something.
enum Stage { kUpdate, kRefit, kSearch, kOrphans, kContacts, kSearchAndSelf, kStep, kStageCount };
/// "update", "refit", "search", "self", "contacts", "search + self", "step"
const char* stage_name(int stage);
/// Whether a stage's serial fraction is reported (not for the two that share their threads).
bool stage_scales_alone(int stage);
/// The time of `stage` in a run, in ms per frame interval.
double stage_ms(const RunRecord& r, int stage);

struct VariantSummary {
  std::string scene, config = "default";
  Method method = Method::Fbd;
  int threads = 1, runs = 0;
  std::array<double, kStageCount> median_ms{}; ///< per frame interval, median over timed runs
  double min_ms = 0, max_ms = 0;                ///< spread of the whole step over timed runs
  /// The speedup over 1 thread paired by round: for each timed run k, the 1-thread run k of
  /// the same scene, configuration and method over this one (run k of every thread count is
  /// taken in one round, minutes apart at most: a machine whose speed moves between rounds
  /// moves both). Median, least and most; NaN without 1-thread runs to pair (and 1 at 1 thread).
  double paired_speedup = 0, paired_min = 0, paired_max = 0;
  RunRecord counts;                             ///< the warm-up run (counts do not vary)
};

/// The median of `v` (the mean of the middle two for an even count; NaN when empty).
double median(std::vector<double> v);

/// Amdahl fit (see the file comment) to (threads, time) points; the point with 1 thread is the
/// base. Returns NaN when there is no point with 1 thread or none with more.
double serial_fraction(const std::vector<std::pair<int, double>>& points);
/// 1 / (s + (1 - s) / threads).
double amdahl_speedup(double s, int threads);

/// The ms per frame interval that a run measured with its stages' work and span (config
/// "work-span", 1 thread) predicts on `threads` threads: its time outside the stages, plus each
/// stage's span + (work - span) / threads (StepStats::predicted_seconds).
double predicted_ms(const RunRecord& measured, int threads);
/// The same prediction scaled to a measured time on `from` threads: `measured_from_ms` x
/// predicted_ms(threads) / predicted_ms(from). The instrumented 1-thread runs take longer than
/// the timed ones and a lent machine's speed moves between runs; the model's ratio between two
/// thread counts is what it knows best.
double predicted_from_ms(const RunRecord& measured, int threads, int from, double measured_from_ms);

/// Groups runs by (scene, configuration, method, threads), in the order they first appear.
std::vector<VariantSummary> summarize(const std::vector<RunRecord>& runs);

/// One scene's figures (the fbd method, or the first method swept when fbd was not).
struct SceneSummary {
  std::string scene, description;
  std::size_t triangles = 0;
  int steps = 0, intervals = 0;
  Method method = Method::Fbd;
  std::vector<int> threads;                 ///< thread counts swept
  std::vector<double> ms;                   ///< median ms per frame at each of them
  /// the speedup over 1 thread paired by round (VariantSummary) at each of them: median, least, most
  std::vector<double> paired, paired_min, paired_max;
  std::array<double, kStageCount> serial{}; ///< serial fraction of each stage
  std::array<double, kStageCount> amdahl16{};
  double volume_tests_traverse = 0, volume_tests_method = 0;  ///< per step; NaN when not swept
  double phc_ms_1 = 0;                      ///< phc median at 1 thread, NaN when not swept
  /// In the paper's configuration (RunRecord::config), NaN when not run: volume tests per step
  /// of traverse and fbd, and per rebuild the front and the adjacent leaf pairs its orphan set
  /// kept out of it.
  double paper_volume_traverse = 0, paper_volume_fbd = 0;
  double front_nodes = 0, front_adjacent = 0;
  double front_mb = 0;                      ///< largest front, MB (10^6 bytes)
  double elementary_tests = 0, contacts = 0;   ///< per step
};

/// Per-scene figures from the variants of that scene.
SceneSummary summarize_scene(const Workload& w, const std::vector<VariantSummary>& variants);

}  // namespace mccd::bench
