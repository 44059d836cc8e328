#pragma once
/// @file Internal: stage 3 of a step (parallel/stepper.cpp), the search: the candidate pairs of
/// the step's method with their leaf pairs and elementary tests (traversal and narrow phase
/// are one stage). By method: brute force over every feature pair (core/brute_force.h); a
/// serial traversal from the root; PHC (parallel/phc.h); FBD, the front tracked in parallel
/// blocks (parallel/front_tracking.h), built from the root first when the front's rebuild
/// rule says so (core/front.h). The stage owns the front and the units' outputs.
#include <cstddef>

#include <mccd/core/brute_force.h>
#include <mccd/core/front.h>
#include <mccd/core/options.h>
#include <mccd/core/query.h>
#include <mccd/core/stats.h>
#include <mccd/core/worker_output.h>
#include <mccd/parallel/contact_buffer.h>
#include <mccd/parallel/front_tracking.h>
#include <mccd/parallel/phc.h>
#include <mccd/parallel/tbb_executor.h>

namespace mccd::detail {

/// The front's rules, from SceneOptions.
struct FrontRules {
  double sprout_ratio = 0.3, invalid_ratio = 0.45;
  std::size_t max_bytes = 0;  ///< 0: no cap
};

class SearchStage {
 public:
  explicit SearchStage(FrontRules rules) : rules_(rules) {
    front_.set_block_nodes(kFrontBlock, kLeastFrontBlock, kMinFrontBlocks);
  }

  /// Runs `method` over `bvtt` (core/bvtt.h) for a step of `kind`, its contacts into
  /// `contacts`, its counts into `stats`. `brute_force` runs the brute-force method into the
  /// WorkerOutput it is given. A query (kind other than Full) reads the front, never changes it.
  template <class Bvtt, class BruteForce>
  void run(Method method, StepKind kind, const Bvtt& bvtt, const BruteForce& brute_force, ContactBuffer& contacts,
           StepStats& stats) {
    switch (method) {
      case Method::BruteForce:
        serial_.clear();
        brute_force(serial_);
        flush(serial_, contacts);
        stats += serial_.stats;
        break;
      case Method::Traverse:
        traverse_serial<false>(bvtt, serial_, contacts);
        stats += serial_.stats;
        break;
      case Method::Phc:
        traverse_phc<false>(bvtt, units_, contacts);
        add(units_.size(), stats);
        break;
      case Method::Fbd:
        if (kind == StepKind::Full)
          fbd(bvtt, contacts, stats);
        else
          fbd_query(bvtt, contacts, stats);
        break;
    }
  }

  const BvttFront& front() const { return front_; }
  /// Forgets the front (after a failed step: it may be half built).
  void invalidate_front() { front_.invalidate(); }

 private:
  template <class Bvtt>
  void fbd(const Bvtt& bvtt, ContactBuffer& contacts, StepStats& stats) {
    if (front_.needs_build()) {
      traverse_phc<true>(bvtt, units_, contacts);
      add(units_.size(), stats);
      front_.build(units_, tbb_executor());
      stats.rebuilds = 1;
    } else {
      const std::size_t n = track_front(bvtt, front_, units_, contacts);
      add(n, stats);
      front_.advance(units_, n, rules_.sprout_ratio, rules_.invalid_ratio, tbb_executor());
    }
    stats.front_bytes = front_.cap(units_, rules_.max_bytes);
    stats.front_size = front_.size();
  }

  template <class Bvtt>
  void fbd_query(const Bvtt& bvtt, ContactBuffer& contacts, StepStats& stats) {
    if (front_.needs_build()) {
      traverse_phc<false>(bvtt, units_, contacts);
      add(units_.size(), stats);
    } else {
      add(track_front(bvtt, front_, units_, contacts, /*readonly=*/true), stats);
    }
  }

  void add(std::size_t n, StepStats& stats) const { add_counts(units_, n, stats); }

  FrontRules rules_;
  BvttFront front_;
  WorkerOutputs units_;  ///< per front block, or per PHC task
  WorkerOutput serial_;  ///< brute force and the serial traversal
};

}  // namespace mccd::detail
