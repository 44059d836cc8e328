#pragma once
/// @file Internal: the BVTT front as one type (paper sections 4.3-4.5, 4.8): its nodes in
/// BVH-node order, sprouting (tracking a block of its nodes), the adaptive rebuild rule of
/// equations 3-4 over the counts since the last build (S: inserted by sprouting, B:
/// invalidated), the memory cap and the reset. The engine cuts the front into blocks and
/// tracks them in parallel (parallel/front_tracking.h); everything else about the front is
/// here.
#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include <mccd/core/bvtt_node.h>
#include <mccd/core/executor.h>
#include <mccd/core/worker_output.h>
#include <mccd/geometry/assert.h>
#include <mccd/geometry/large_allocator.h>

namespace mccd::detail {

class BvttFront {
 public:
  /// Whether the next fbd step must build the front from the root.
  bool needs_build() const { return !valid_; }
  const LargeVector<NodePair>& nodes() const { return nodes_; }
  std::size_t size() const { return nodes_.size(); }
  /// Where the blocks of the next tracking start (ascending, from 0, and the front's size
  /// last), cut by advance() and build() so that each block holds about the same work as
  /// measured in the last step (after a build: the traversal's work spread over the front,
  /// its costly leaf pairs where they lie); empty for an empty front (blocks of a fixed size
  /// then). Counts only, so the cuts, like the front, do not depend on the thread count.
  const std::vector<std::uint32_t>& cuts() const { return cuts_; }

  /// A fresh front from the pieces of a traversal from the root (concatenated in piece order,
  /// then sorted by first node: BVH-node order, section 4.8). The pieces are released.
  void build(WorkerOutputs& pieces, const Executor& ex = serial_executor());
  /// The next front from the outputs of the tracked blocks, in block order; adds their S and B
  /// counts and applies the rebuild rule: when S/L > sprout_ratio or B/L > invalid_ratio (L the
  /// new front size), the next step rebuilds. The blocks' parts are copied through `ex`, each
  /// to its own place.
  void advance(const WorkerOutputs& blocks, std::size_t num_blocks, double sprout_ratio, double invalid_ratio,
               const Executor& ex = serial_executor());
  /// The units of work of a tracked block, from its counts (a rough cost: its leaf pairs'
  /// set-up, feature pairs and elementary tests, and its volume tests).
  static double work_of(const StepStats& s);
  /// The work every front node adds to its block besides work_of's (visiting it, reading its
  /// nodes' volumes), in work_of's units.
  static constexpr double kNodeWork = 15.0;
  /// Block sizes: a front of n nodes is tracked in blocks of block_size(n) nodes, `most` where
  /// that gives at least `min_blocks` blocks, else smaller ones, down to `least` (a small
  /// front is still spread over many threads). The cuts give the next tracking as many
  /// blocks as fixed blocks of that size would, of about equal work, none longer than 4
  /// block sizes. A size of the front only, never of the thread count.
  void set_block_nodes(std::size_t most, std::size_t least = 0, std::size_t min_blocks = 1) {
    most_nodes_ = std::max<std::size_t>(most, 1);
    least_nodes_ = least == 0 ? most_nodes_ : std::clamp<std::size_t>(least, 1, most_nodes_);
    min_blocks_ = std::max<std::size_t>(min_blocks, 1);
  }
  std::size_t block_size(std::size_t n) const { return std::clamp(n / min_blocks_, least_nodes_, most_nodes_); }
  /// The memory cap: the bytes held by the front and by the parts of it in `units`; over
  /// `max_bytes` (0: no cap) both are released and the next step rebuilds. Returns the bytes
  /// held after it.
  std::size_t cap(WorkerOutputs& units, std::size_t max_bytes);
  /// Forgets the front: the next fbd step builds it from the root (after a failed step).
  void invalidate() {
    valid_ = false;
    cuts_.clear();
  }
  /// Forgets the front and releases its buffers.
  void release() {
    valid_ = false;
    nodes_ = LargeVector<NodePair>();
    next_ = LargeVector<NodePair>();
    cuts_ = std::vector<std::uint32_t>();
  }
  /// Bytes held by the front buffers.
  std::size_t bytes() const { return (nodes_.capacity() + next_.capacity()) * sizeof(NodePair); }

  /// Sprouting: tracks front nodes [begin, end) over `bvtt` (core/bvtt.h) into `out` (paper
  /// sections 4.3-4.4). A disjoint node stays; an overlapping leaf pair is processed and
  /// stays; an overlapping inner node is replaced by the stops of its subtree (no pruning);
  /// a node covered by a self-culling certificate stays untested. out.front receives this
  /// block's part of the next front, out.stats its S and B counts. The block's sprouts do at
  /// most `max_work` units of work together (Bvtt::traverse): what is left of a sprout past
  /// that goes to out.left, for the caller to traverse (recording the stops: the rest of the
  /// next front, all of it sprouted).
  template <class Bvtt>
  static void track(const Bvtt& bvtt, const NodePair* begin, const NodePair* end, WorkerOutput& out,
                    std::size_t max_work = static_cast<std::size_t>(-1));
  /// The same tests for a query: the front is read, not changed (nothing is recorded;
  /// overlapping inner nodes are traversed below, up to `max_work` as in track()). Stops
  /// when the query stops.
  template <class Bvtt>
  static void track_readonly(const Bvtt& bvtt, const NodePair* begin, const NodePair* end, WorkerOutput& out,
                             std::size_t max_work = static_cast<std::size_t>(-1));

 private:
  static constexpr int kAhead = 8;  ///< front nodes ahead whose volumes are prefetched
  /// A part of the next front for cut(): nodes [begin, end), their work (work_of), and its
  /// costly nodes (at: from begin, ascending).
  struct Part {
    std::size_t begin, end;
    double work;
    std::span<const CostlyNode> costly;
  };
  /// Cuts the front into blocks of about equal work: each part's costly nodes where they lie,
  /// the rest of its work spread evenly over its other nodes.
  void cut(const std::vector<Part>& parts);
  LargeVector<NodePair> nodes_, next_;
  std::vector<std::uint32_t> cuts_;
  std::size_t most_nodes_ = 64, least_nodes_ = 64, min_blocks_ = 1;
  std::uint64_t sprouted_since_build_ = 0, invalidated_since_build_ = 0;
  bool valid_ = false;
};

/// Traverses out.stack for what is left of `budget` (units of Bvtt::traverse); hands the rest
/// to out.left.
template <bool record, class Bvtt>
void sprout_within(const Bvtt& bvtt, WorkerOutput& out, std::size_t& budget) {
  budget -= std::min(budget, bvtt.template traverse<record>(out, budget));
  if (!out.stack.empty()) {
    out.left.insert(out.left.end(), out.stack.begin(), out.stack.end());
    out.stack.clear();
  }
}

template <class Bvtt>
void BvttFront::track(const Bvtt& bvtt, const NodePair* begin, const NodePair* end, WorkerOutput& out,
                      std::size_t max_work) {
  const auto& bvh = bvtt.bvh();
  std::size_t budget = max_work;
  for (const NodePair* it = begin; it != end; ++it) {
    const NodePair n = *it;
    MCCD_ASSERT(n.a < bvh.size() && n.b < bvh.size() && n.a <= n.b, "front node out of range");
    if (it + kAhead < end) bvtt.prefetch(it[kAhead]);  // the node volumes a few nodes ahead
    if (bvtt.culled(n, out)) {
      out.front.push_back(n);
      continue;
    }
    if (n.a == n.b) {  // a self node kept while it was covered
      ++out.stats.invalidated;
      const std::size_t before = out.front.size();
      out.stack.push_back(n);
      sprout_within<true>(bvtt, out, budget);
      out.stats.sprouted += out.front.size() - before;
      continue;
    }
    ++out.stats.volume_tests;
    const unsigned ov = bvtt.quarters(n);
    if (bvh.leaf(n.a) && bvh.leaf(n.b)) {
      if (ov) {
        // its work, as the next cuts count it: the feature pairs it tested and those it queued
        const std::uint64_t before = out.pair_work();
        bvtt.leaf().process(n.a, n.b, ov, out);
        out.note_leaf_pair(out.front.size(), out.pair_work() - before);
      }
      out.front.push_back(n);
    } else if (!ov) {
      out.front.push_back(n);
    } else {
      ++out.stats.invalidated;
      const std::size_t before = out.front.size();
      bvtt.push_children(n, out.stack);
      sprout_within<true>(bvtt, out, budget);
      out.stats.sprouted += out.front.size() - before;
    }
  }
  bvtt.finish(out);
}

template <class Bvtt>
void BvttFront::track_readonly(const Bvtt& bvtt, const NodePair* begin, const NodePair* end, WorkerOutput& out,
                               std::size_t max_work) {
  const auto& bvh = bvtt.bvh();
  std::size_t budget = max_work;
  for (const NodePair* it = begin; it != end && !bvtt.stopped(); ++it) {
    const NodePair n = *it;
    MCCD_ASSERT(n.a < bvh.size() && n.b < bvh.size() && n.a <= n.b, "front node out of range");
    if (bvtt.culled(n, out)) continue;
    if (n.a == n.b) {
      out.stack.push_back(n);
      sprout_within<false>(bvtt, out, budget);
      continue;
    }
    ++out.stats.volume_tests;
    const unsigned ov = bvtt.quarters(n);
    if (!ov) continue;
    if (bvh.leaf(n.a) && bvh.leaf(n.b)) {
      bvtt.leaf().process(n.a, n.b, ov, out);
    } else {
      bvtt.push_children(n, out.stack);
      sprout_within<false>(bvtt, out, budget);
    }
  }
  bvtt.finish(out);
}

}  // namespace mccd::detail
