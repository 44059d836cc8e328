#pragma once
/// @file Internal: what one unit of work (a block of the front, a task of a traversal, a serial
/// pass) produces: its part of the next front, its contacts, its counters. Each unit writes
/// only its own output; outputs are joined after the parallel loop, in unit order, so the
/// result does not depend on scheduling.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include <mccd/core/bvtt_node.h>
#include <mccd/core/contact.h>
#include <mccd/geometry/large_allocator.h>

namespace mccd::detail {

/// A contact as found: its key (kind, then global ids a and b: VF vertex and face, EE edge
/// a < edge b), which orders contacts canonically (global ids number the meshes in order), its
/// time and the four vertices of its elementary test (global ids; EE: a's ends, then b's).
struct RawContact {
  std::uint64_t key;          ///< 8 bytes: kind << 63 | a << 32 | b (ids below 2^31)
  double toi;                 ///< 8 bytes
  std::uint32_t vertices[4];  ///< 16 bytes
  static std::uint64_t make_key(ContactKind kind, std::uint32_t a, std::uint32_t b) {
    return std::uint64_t(kind == ContactKind::EdgeEdge) << 63 | std::uint64_t(a) << 32 | b;
  }
  ContactKind kind() const { return key >> 63 ? ContactKind::EdgeEdge : ContactKind::VertexFace; }
  std::uint32_t a() const { return static_cast<std::uint32_t>(key >> 32) & 0x7fffffffu; }
  std::uint32_t b() const { return static_cast<std::uint32_t>(key); }
};
static_assert(sizeof(RawContact) == 32);

/// A feature pair past its volume tests, queued for the narrow phase (core/feature_tests.h,
/// which runs queued pairs together): its points and ids as reported, the quarters where its
/// volumes meet, and the leaves where it was found (a leaf pair, or one leaf twice).
struct QueuedPair {
  std::uint32_t ids[4];
  std::uint32_t a, b;
  std::uint32_t leaf_a, leaf_b;
  std::uint8_t kind, quarters;  ///< kind: 0 vertex-face, 1 edge-edge; quarters: the 4-bit mask
};

/// The queue of feature pairs a unit waits to send to the narrow phase: a plain array that
/// grows and is emptied, no more. Besides push_back(), a loop that decides per pair whether to
/// keep it can write every pair at the end (room()) and advance the end only by the pairs it
/// keeps (set_end()), without a branch on the decision.
class PairQueue {
 public:
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  QueuedPair* data() { return data_.get(); }
  const QueuedPair* data() const { return data_.get(); }
  void clear() {
    emptied_ += size_;
    size_ = 0;
  }
  /// Pairs ever queued here (those emptied and those waiting): differences of it count what a
  /// stretch of work queued, whatever ran the queue in between.
  std::uint64_t total() const { return emptied_ + size_; }
  void push_back(const QueuedPair& p) {
    if (size_ == capacity_) grow(size_ + 1);
    data_[size_++] = p;
  }
  /// The end of the queue, with room for `n` entries written from there.
  QueuedPair* room(std::size_t n) {
    if (size_ + n > capacity_) grow(size_ + n);
    return data_.get() + size_;
  }
  /// The queue ends at `end` (from room(): entries written before it are kept).
  void set_end(const QueuedPair* end) { size_ = static_cast<std::size_t>(end - data_.get()); }

 private:
  void grow(std::size_t need) {
    const std::size_t capacity = std::max({need, 2 * capacity_, std::size_t(1024)});
    std::unique_ptr<QueuedPair[]> data(new QueuedPair[capacity]);  // left uninitialised
    if (size_) std::memcpy(data.get(), data_.get(), size_ * sizeof(QueuedPair));
    data_ = std::move(data);
    capacity_ = capacity;
  }
  std::unique_ptr<QueuedPair[]> data_;
  std::size_t size_ = 0, capacity_ = 0;
  std::uint64_t emptied_ = 0;
};

/// A front node whose leaf pair cost much more than most (noted where it is recorded:
/// BvttFront::track, Bvtt::traverse): its place in the unit's part of the next front and its
/// work, in BvttFront::work_of's units.
struct CostlyNode {
  /// work_of's units (a feature-pair test): a leaf pair's set-up, and the work from which a
  /// leaf pair is noted (with its feature pairs, WorkerOutput::pair_work()).
  static constexpr std::uint64_t kLeafPairWork = 48, kCostlyWork = 2048;
  std::uint32_t at;
  std::uint32_t work;
};

struct WorkerOutput {
  std::vector<NodePair> front;       ///< the front nodes this unit keeps or sprouts
  std::vector<RawContact> contacts;  ///< found by this unit, not yet handed to the buffer
  std::vector<NodePair> stack;       ///< traversal stack (kept to reuse the allocation)
  /// Nodes this unit left to be traversed by tasks of their own (a sprout past its block's
  /// budget of work, BvttFront::track).
  std::vector<NodePair> left;
  PairQueue queued;                  ///< feature pairs waiting for the narrow phase
  StepStats stats;                   ///< this unit's counts
  std::vector<CostlyNode> costly;    ///< front tracking: its costly nodes, in order
  /// A queued feature pair's weight against a tested one (its filter and its share of
  /// elementary tests).
  static constexpr std::uint64_t kQueuedPairWork = 9;
  /// The feature pairs this unit has tested and queued so far, in feature-pair tests: the
  /// difference over a leaf pair weighs it (front cuts, traversal budgets), whatever ran the
  /// queue in between.
  std::uint64_t pair_work() const { return stats.feature_box_tests + kQueuedPairWork * queued.total(); }
  /// Notes the front node at `at` as costly when its leaf pair's work (its set-up and
  /// `pair_work`, the pair_work() it added) reaches CostlyNode::kCostlyWork.
  void note_leaf_pair(std::size_t at, std::uint64_t pair_work) {
    const std::uint64_t work = CostlyNode::kLeafPairWork + pair_work;
    if (work >= CostlyNode::kCostlyWork)
      costly.push_back(
          {static_cast<std::uint32_t>(at), static_cast<std::uint32_t>(std::min<std::uint64_t>(work, 0xffffffffu))});
  }
  void clear() {
    front.clear();
    costly.clear();
    contacts.clear();
    stack.clear();
    left.clear();
    queued.clear();
    stats = {};
  }
};

/// The outputs of a parallel loop, one per unit. Thousands of units make megabytes of
/// outputs, first touched in the step: huge pages (geometry/large_allocator.h) make that cheap.
using WorkerOutputs = std::vector<WorkerOutput, LargeAllocator<WorkerOutput>>;

}  // namespace mccd::detail
