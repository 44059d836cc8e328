#pragma once
/// @file Internal: the BVTT front as a type (paper sections 4.3-4.5, 4.8). Its nodes in BVH-node
/// order, the counts since the last build (S: inserted by sprouting, B: invalidated), and the
/// adaptive rebuild rule of equations 3-4.
#include <cstdint>
#include <vector>

#include <mccd/core/worker_output.h>
#include <mccd/geometry/large_allocator.h>

namespace mccd::detail {

class BvttFront {
 public:
  /// Whether the next fbd step must build the front from the root.
  bool needs_build() const { return !valid_; }
  const LargeVector<NodePair>& nodes() const { return nodes_; }
  std::size_t size() const { return nodes_.size(); }

  /// A fresh front from the pieces of a traversal from the root (concatenated in piece order,
  /// then sorted by first node: BVH-node order, section 4.8). The pieces are released.
  void build(WorkerOutputs& pieces);
  /// The next front from the outputs of the tracked blocks, in block order; adds their S and B
  /// counts and applies the rebuild rule: when S/L > sprout_ratio or B/L > invalid_ratio (L the
  /// new front size), the next step rebuilds.
  void advance(const WorkerOutputs& blocks, std::size_t num_blocks, double sprout_ratio,
               double invalid_ratio);
  /// Forgets the front: the next fbd step builds it from the root.
  void invalidate() { valid_ = false; }
  /// Forgets the front and releases its buffers (the memory cap).
  void release() {
    valid_ = false;
    nodes_ = LargeVector<NodePair>();
    next_ = LargeVector<NodePair>();
  }
  /// Bytes held by the front buffers.
  std::size_t bytes() const { return (nodes_.capacity() + next_.capacity()) * sizeof(NodePair); }

 private:
  LargeVector<NodePair> nodes_, next_;
  std::uint64_t sprouted_since_build_ = 0, invalidated_since_build_ = 0;
  bool valid_ = false;
};

}  // namespace mccd::detail
