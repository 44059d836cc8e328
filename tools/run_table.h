#pragma once
/// @file What `mccd run` prints: one row per step (a frame interval, its sub-steps taken
/// together), the legend (the frames' files; the --verbose columns), and the summary at the end,
/// which names the steps by their files and says where and why a run stopped early.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <mccd/core/contact.h>
#include <mccd/geometry/large_allocator.h>

#include "time_text.h"

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
  /// The pairs of the step's sub-steps so far, in sorted runs, each pair once in a run (run j
  /// in [runs_[j], runs_[j + 1]), holding 2^levels_[j] sub-steps): a sub-step adds a run, and
  /// the last two runs are merged while they hold as many sub-steps (a binary counter), so that
  /// the merging goes on beside the next sub-steps and little is left after the last.
  mccd::detail::LargeVector<PairKey> keys_, scratch_;
  std::vector<std::size_t> runs_;
  std::vector<unsigned> levels_;
  /// Merges the last two runs into one, sorted, a pair found in both kept once.
  void merge_last_two();
};

/// How the summary names frames and steps: by the files the frames came from (their names
/// without the folder), else by number.
class FrameNames {
 public:
  /// Frames named by number ("frame 3").
  FrameNames() = default;
  /// Frame i named files[i] without its folder ("cloth_ball92.ply").
  explicit FrameNames(const std::vector<std::string>& files);
  /// "cloth_ball92.ply", or "frame 3".
  std::string frame(std::size_t i) const;
  /// Frames a to b: "frame000.ply to frame005.ply", or "frames 0 to 5".
  std::string frames(std::size_t a, std::size_t b) const;
  /// The step from frame k to k + 1: "cloth_ball92.ply to cloth_ball93.ply", or "frame 3 to 4".
  std::string step(std::size_t k) const;
  /// Whether frames are named by files.
  bool named() const { return !names_.empty(); }
  /// The frames' files by number, for the table's legend: "frame 0 = a.ply, frame 1 = b.ply"
  /// (with "..." between the first two and the last when there are more than three); "" when
  /// not named by files.
  std::string key(std::size_t frames) const;

 private:
  std::vector<std::string> names_;
};

/// The per-step table: step, VF, EE, first impact, time; --verbose adds the statistics.
class RunTable {
 public:
  explicit RunTable(bool verbose) : verbose_(verbose) {}
  /// What the columns mean; the step numbers' frames (their files) always, the statistics'
  /// columns with --verbose.
  void print_legend(const FrameNames& names, std::size_t frames) const;
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

/// Why and where a run stopped before its last step.
struct RunStop {
  std::size_t steps = 0;  ///< steps in the whole run
  std::size_t step = 0;   ///< the step it stopped at (the steps before it finished)
  std::string why;        ///< the error, naming the file and frame
};

/// The summary: steps and those with contacts, contacts by kind, the first impact and its
/// step (both named by `names`), time per step; `wall`: seconds in all. With `stop`, the
/// first line says that the run stopped, at which step (its frames) and why, and the totals
/// are those of the steps finished before it.
void print_summary(const RunTotals& t, const FrameNames& names, const char* method, int threads, double wall,
                   const RunStop* stop = nullptr);

}  // namespace mccd::cli
