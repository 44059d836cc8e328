#pragma once
/// @file Internal: leaves that repeat the previous step (leaf rule). What a leaf pair finds
/// depends only on the start and end positions of its two leaves' corners (their volumes, the
/// pair's quarter mask and every elementary test are functions of them and of the scene's
/// fixed options). When every corner of both leaves has bit for bit the start and end
/// positions of the previous full step, and neither leaf took part in a contact then, the pair
/// finds nothing now either: it overlapped then as it does now, so it was processed (every
/// method but brute force processes every overlapping leaf pair), and found nothing. Such a
/// pair, and such a leaf's own pairs, are skipped. Parts of a scene at rest (the folding
/// cloth's unmoving half, a draped cloth that has settled, an environment given as deforming)
/// then cost a flag test per leaf pair instead of their feature tests. The leaves of static
/// meshes always repeat, so a resting mesh's pairs with them are skipped too.
///
/// Per step (full steps only; a query step neither uses nor changes this):
///  1. begin(): the previous step's contacts are in `touched` (set by the leaf pairs and
///     single leaves that found one); they become `touched_before`;
///  2. the update compares each vertex's positions with the previous step's and keeps them,
///     then recomputes the volumes of the vertices, edges and faces that do not repeat;
///  3. the refit marks each leaf whose corners all repeat, and keeps its volume;
///  4. leaf pairs and single leaves ask skip(), and mark the leaves of every pair that finds a
///     contact (relaxed atomic stores of 1: several blocks may mark one leaf).
#include <atomic>
#include <cstdint>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

#include <mccd/geometry/large_allocator.h>
#include <mccd/geometry/positions.h>

namespace mccd::detail {

class UnchangedLeaves {
 public:
  /// Whether this step may skip (set by begin()).
  bool active() const { return active_; }

  /// The leaves of static meshes (per BVH node, 1 for such a leaf): their positions never
  /// change (the scene checks it), so they always repeat; the refit never visits them.
  void set_static(std::vector<std::uint8_t> leaves) { static_ = std::move(leaves); }

  /// A full step starts: `usable` when the previous step was a full step that processed its
  /// leaf pairs (not brute force) and completed. Then the previous step's marks become
  /// touched_before; the marks are cleared either way.
  void begin(std::size_t num_nodes, std::size_t num_vertices, bool usable) {
    if (touched_size_ != num_nodes) {
      touched_ = std::make_unique<std::atomic<std::uint8_t>[]>(num_nodes);
      touched_size_ = num_nodes;
      touched_before_.assign(num_nodes, 0);
      unchanged_ = static_.size() == num_nodes ? static_ : std::vector<std::uint8_t>(num_nodes, 0);
      usable = false;
    }
    if (same_.size() != num_vertices) {
      reserve_backed(prev0_, 3 * num_vertices);  // written in full by the first compare()
      reserve_backed(prev1_, 3 * num_vertices);
      prev0_.resize(3 * num_vertices);
      prev1_.resize(3 * num_vertices);
      same_.assign(num_vertices, 0);
      usable = false;
    }
    active_ = usable && have_prev_;
    recording_ = true;
    for (std::size_t i = 0; i < num_nodes; ++i) {
      touched_before_[i] = active_ ? touched_[i].load(std::memory_order_relaxed) : 0;
      touched_[i].store(0, std::memory_order_relaxed);
    }
  }
  /// The step did not complete, or was a query: the next step starts without a previous one.
  void forget() {
    have_prev_ = false;
    active_ = recording_ = false;
  }

  /// Vertices [begin, end) after the step's positions are known: whether each repeats the
  /// previous step's start and end bit for bit; then this step's become the previous ones.
  void compare(const Positions& x0, const Positions& x1, std::size_t begin, std::size_t end) {
    const double* a = x0.data();
    const double* b = x1.data();
    double* p = prev0_.data();  // written before read: the first compare() is not used
    double* q = prev1_.data();
    for (std::size_t v = begin; v != end; ++v) {
      same_[v] = std::memcmp(a + 3 * v, p + 3 * v, 3 * sizeof(double)) == 0 &&
                 std::memcmp(b + 3 * v, q + 3 * v, 3 * sizeof(double)) == 0;
      std::memcpy(p + 3 * v, a + 3 * v, 3 * sizeof(double));
      std::memcpy(q + 3 * v, b + 3 * v, 3 * sizeof(double));
    }
  }
  /// The step completed: its positions are the previous ones for the next step.
  void end() { have_prev_ = true; }

  /// Leaf `leaf` after compare() (only when active()): whether all its corners repeat.
  /// `owners`: the LeafOwnership (core/leaf_rule_owners.h).
  template <class Owners>
  bool mark_leaf(std::uint32_t leaf, const Owners& owners) {
    bool same = true;
    for (std::uint32_t s = owners.vertex_begin(leaf); s != owners.vertex_begin(leaf + 1); ++s)
      same &= same_[owners.vertex(s)] != 0;
    for (std::uint32_t i = owners.foreign_begin(leaf); i != owners.foreign_begin(leaf + 1); ++i)
      same &= same_[owners.vertex(owners.foreign_corner(i))] != 0;
    unchanged_[leaf] = same;
    return same;
  }

  /// Per vertex id after compare(), when active(): whether it repeats the previous step (its
  /// volumes from then hold).
  const std::uint8_t* same() const { return same_.data(); }

  /// Whether leaf pair (a, b) (a == b: one leaf's own pairs) finds nothing, as before.
  bool skip(std::uint32_t a, std::uint32_t b) const {
    return active_ && (unchanged_[a] & unchanged_[b] & !touched_before_[a] & !touched_before_[b]);
  }
  /// Leaf pair (a, b) (or leaf a alone) found a contact (recorded in full steps only).
  void touched(std::uint32_t a, std::uint32_t b) const {
    if (!recording_) return;
    touched_[a].store(1, std::memory_order_relaxed);
    touched_[b].store(1, std::memory_order_relaxed);
  }

 private:
  bool active_ = false, have_prev_ = false;
  bool recording_ = false;  ///< between begin() and forget(): a full step marks its leaves
  LargeVector<double> prev0_, prev1_;  ///< the previous full step's start and end, interleaved
  std::vector<std::uint8_t> same_;   ///< per vertex: repeats the previous step
  std::vector<std::uint8_t> unchanged_, touched_before_;  ///< per BVH node (leaves)
  std::vector<std::uint8_t> static_;  ///< per BVH node: a leaf of a static mesh
  std::unique_ptr<std::atomic<std::uint8_t>[]> touched_;  ///< per BVH node: this step's marks
  std::size_t touched_size_ = 0;
};

}  // namespace mccd::detail
