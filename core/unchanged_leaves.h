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
///  2. the update notes, vertex by vertex as it reads them (note(), by storage slot), whether
///     its start and end differ, and recomputes the volumes of the vertices that do not
///     repeat. When this step's start is bit for bit the previous step's end (Scene::advance,
///     or a step whose start equals the last end: `continues`), a vertex repeats the previous
///     step exactly when it moved in neither step, so no positions are kept or compared beyond
///     the step's own. A step that does not continue the last skips nothing (its motion is
///     noted for the next);
///  3. the refit marks each leaf whose corners all repeat, and keeps its volume;
///  4. leaf pairs and single leaves ask skip(), and mark the leaves of every pair that finds a
///     contact (relaxed atomic stores of 1: several blocks may mark one leaf).
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

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
  /// leaf pairs (not brute force) and completed; `continues` when this step's start positions
  /// are bit for bit the end positions of the previous full step. With both (and the previous
  /// step's motion noted), it may skip; the previous step's marks then become touched_before.
  /// The marks are cleared either way.
  void begin(std::size_t num_nodes, std::size_t num_vertices, bool usable, bool continues) {
    if (touched_.size() != num_nodes) {
      touched_.assign(num_nodes, 0);
      touched_before_.assign(num_nodes, 0);
      unchanged_ = static_.size() == num_nodes ? static_ : std::vector<std::uint8_t>(num_nodes, 0);
      usable = false;
    }
    if (moved_.size() != num_vertices) {
      // A vertex the update never notes (a static mesh's) never moves: it repeats.
      moved_.assign(num_vertices, 0);
      moved_before_.assign(num_vertices, 0);
      usable = have_prev_ = false;
    }
    active_ = usable && continues && have_prev_;
    recording_ = true;
    // The last step's marks become touched_before_ (read only when active_); this step's
    // start clear. A swap and a fill: no step runs now, so no mark is being written.
    std::swap(touched_, touched_before_);
    std::fill(touched_.begin(), touched_.end(), std::uint8_t(0));
  }
  /// The step did not complete, or was a query: the next step starts without a previous one.
  void forget() {
    have_prev_ = false;
    active_ = recording_ = false;
  }

  /// The vertex in storage slot `slot` (the swept volumes' layout: each update chunk writes
  /// its own run of slots), its start `a` and end `b` (three doubles each) in this step's
  /// update: every moving vertex once per full step. Records whether it moves, and returns
  /// whether it repeats the previous full step bit for bit (only when active(): its volumes
  /// from then hold).
  [[gnu::always_inline]] bool note(std::size_t slot, const double* a, const double* b) {
    const bool moved = std::memcmp(a, b, 3 * sizeof(double)) != 0;
    moved_[slot] = moved;
    // continues: this start is the previous end, so the previous start equals it exactly when
    // the vertex did not move then, and this end equals it when it does not move now
    return active_ && !moved && !moved_before_[slot];
  }
  /// The step completed: the motion it noted is the previous step's for the next.
  void end() {
    std::swap(moved_, moved_before_);
    have_prev_ = true;
  }

  /// Leaf `leaf` after the update (only when active()): whether all its corners repeat.
  /// `owners`: the LeafOwnership (core/leaf_rule_owners.h), whose slots note() was given.
  template <class Owners>
  bool mark_leaf(std::uint32_t leaf, const Owners& owners) {
    auto repeats = [&](std::uint32_t slot) { return (moved_[slot] | moved_before_[slot]) == 0; };
    bool same = true;
    for (std::uint32_t s = owners.vertex_begin(leaf); s != owners.vertex_begin(leaf + 1); ++s) same &= repeats(s);
    for (std::uint32_t i = owners.foreign_begin(leaf); i != owners.foreign_begin(leaf + 1); ++i)
      same &= repeats(owners.foreign_corner(i));
    unchanged_[leaf] = same;
    return same;
  }

  /// Whether leaf `leaf` repeats the previous full step (only when active(), after the refit
  /// marked it, or of a static mesh): its corners' start and end positions and its volume.
  bool repeats(std::uint32_t leaf) const { return active_ && unchanged_[leaf]; }

  /// Whether every leaf under BVH node `node` repeats the previous full step (only when
  /// active(), after the refit marked the leaves): all their corners' positions are the ones
  /// they had then, and so are the volumes of the node and of every node below it.
  template <class Bvh>
  bool subtree_repeats(std::uint32_t node, const Bvh& bvh) const {
    if (!active_) return false;
    for (std::uint32_t i = node, end = node + bvh.subtree_size(node); i != end; ++i)
      if (bvh.leaf(i) && !unchanged_[i]) return false;
    return true;
  }

  /// Whether leaf pair (a, b) (a == b: one leaf's own pairs) finds nothing, as before.
  bool skip(std::uint32_t a, std::uint32_t b) const {
    return active_ && (unchanged_[a] & unchanged_[b] & !touched_before_[a] & !touched_before_[b]);
  }
  /// Leaf pair (a, b) (or leaf a alone) found a contact (recorded in full steps only).
  void touched(std::uint32_t a, std::uint32_t b) const {
    if (!recording_) return;
    std::atomic_ref<std::uint8_t>(touched_[a]).store(1, std::memory_order_relaxed);
    std::atomic_ref<std::uint8_t>(touched_[b]).store(1, std::memory_order_relaxed);
  }

 private:
  bool active_ = false;
  bool have_prev_ = false;  ///< moved_before_ holds the motion of the previous full step
  bool recording_ = false;  ///< between begin() and forget(): a full step marks its leaves
  /// Per vertex slot: start and end differ, in this full step / in the previous one.
  std::vector<std::uint8_t> moved_, moved_before_;
  std::vector<std::uint8_t> unchanged_, touched_before_;  ///< per BVH node (leaves)
  std::vector<std::uint8_t> static_;  ///< per BVH node: a leaf of a static mesh
  /// Per BVH node: this step's marks (set through std::atomic_ref by the step's threads).
  mutable std::vector<std::uint8_t> touched_;
};

}  // namespace mccd::detail
