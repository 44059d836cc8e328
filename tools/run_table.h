#pragma once
/// @file What `mccd run` prints: one row per step (a frame interval, its sub-steps taken
/// together), the legend of the --verbose columns, and the summary at the end.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <limits>
#include <vector>

#include <mccd/core/contact.h>

namespace mccd::cli {

/// One step: frame `step` to `step` + 1, all its sub-steps.
struct StepRow {
  std::size_t step = 0;
  std::size_t vf = 0, ee = 0;  ///< pairs in contact during the step, each pair once
  double first = std::numeric_limits<double>::infinity();  ///< earliest time of impact, frame time
  StepStats stats;  ///< summed over the sub-steps (the front size: after the last)
};

/// Gathers the sub-steps of a step into its row.
class StepAccumulator {
 public:
  explicit StepAccumulator(int substeps) : substeps_(substeps) {}
  /// Adds sub-step `substep` of `step`; returns true when it was the step's last, and row()
  /// is then the whole step's.
  bool add(std::size_t step, std::size_t substep, const StepResult& r);
  const StepRow& row() const { return row_; }

 private:
  int substeps_;
  StepRow row_;
  /// A contact's pair as two words, ordered as the contacts (mesh ids below 2^31).
  using PairKey = std::pair<std::uint64_t, std::uint64_t>;
  static PairKey key(const Contact& c);
  std::vector<PairKey> pairs_;  // the step's pairs so far, sorted, each once
  std::vector<PairKey> merged_, keys_;
};

/// The per-step table: step, VF, EE, first impact, time; --verbose adds the statistics.
class RunTable {
 public:
  explicit RunTable(bool verbose) : verbose_(verbose) {}
  void print_legend() const;
  void print_header() const;
  void print_row(const StepRow& row) const;

 private:
  bool verbose_;
};

/// Totals over the run, for the summary.
struct RunTotals {
  std::size_t steps = 0, steps_with_contacts = 0, vf = 0, ee = 0;
  double first = std::numeric_limits<double>::infinity();  ///< frame time
  std::size_t first_step = 0;
  double step_seconds = 0;
  void add(const StepRow& row);
};

/// The summary: steps and those with contacts, contacts by kind, the first impact and its
/// step, time per step. `frames`: frames in the run; `wall`: seconds in all.
void print_summary(const RunTotals& t, std::size_t frames, const char* method, int threads, double wall);

/// "0.0625" (frame time of an impact), or "-" when there is none.
std::string impact_text(double frame_time);

}  // namespace mccd::cli
