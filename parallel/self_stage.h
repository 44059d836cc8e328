#pragma once
/// @file Internal: stage 4 of a step (parallel/stepper.cpp), the self stage, beside the search:
/// the feature pairs no BVTT pair node holds (each leaf's own pairs under the leaf rule; the
/// orphan set and the pairs inside leaves under the canonical rule: core/leaf_pairs.h), in
/// fixed blocks of self units, each with its own output, added in block order.
#include <algorithm>
#include <cstddef>

#include <oneapi/tbb/partitioner.h>

#include <mccd/core/stats.h>
#include <mccd/core/worker_output.h>
#include <mccd/parallel/contact_buffer.h>
#include <mccd/parallel/front_tracking.h>
#include <mccd/parallel/tbb_executor.h>

namespace mccd::detail {

class SelfStage {
 public:
  /// Self units per block: 16 leaves of up to 21 triangles; fewer, down to kLeastBlock, where
  /// that gives fewer than kMinBlocks blocks, so that small scenes still spread over many
  /// threads (a size of the scene only, never of the thread count).
  static constexpr std::size_t kBlock = 16, kLeastBlock = 2, kMinBlocks = 64;
  /// Units up to which the stage runs on the calling thread (as front tracking does: a
  /// parallel loop costs more in waking threads than it saves there).
  static constexpr std::size_t kSerialUnits = 4 * kBlock;

  /// Self units per block for `units` in all.
  static std::size_t block_size(std::size_t units) { return std::clamp(units / kMinBlocks, kLeastBlock, kBlock); }

  /// Every self unit of `leaf` (core/leaf_pairs.h), contacts into `contacts`, counts into
  /// `stats`.
  template <class Leaf>
  void run(const Leaf& leaf, ContactBuffer& contacts, StepStats& stats) {
    const std::size_t units = leaf.num_self_units(), size = block_size(units), n = (units + size - 1) / size;
    if (outputs_.size() < n) outputs_.resize(n);
    auto block = [&](std::size_t b) {
      WorkerOutput& o = outputs_[b];
      o.clear();
      leaf.process_self(b * size, std::min(units, (b + 1) * size), o);
      flush(o, contacts);
    };
    if (units <= kSerialUnits)
      for (std::size_t b = 0; b < n; ++b) block(b);
    else
      for_each_index(n, block, tbb::auto_partitioner());
    add_counts(outputs_, n, stats);
  }

 private:
  WorkerOutputs outputs_;  ///< per block, kept from step to step
};

}  // namespace mccd::detail
