#pragma once
/// @file Internal: BVH refit as a static partition (paper section 4.7). The BVH never changes
/// shape, so its cut into subtrees of similar size is planned once; every step refits the
/// subtrees under a static partition (fixed work per subtree), then the few nodes above the
/// cut serially, deepest first. A BVH small enough to be one subtree is refitted serially,
/// without creating a task (Embree's bvh_refit does the same).
#include <algorithm>
#include <cstdint>
#include <vector>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>

#include <mccd/core/bvh.h>

namespace mccd::detail {

class RefitPlan {
 public:
  RefitPlan() = default;
  /// Cuts the BVH into subtrees of at most ~1/64 of the nodes, and at least `min_subtree`
  /// nodes so that small scenes stay one piece. Subtrees whose triangles never move
  /// (`is_static(node)`) are set apart: refitted once by run_static(), never by run().
  /// Nodes above the meshes' subtrees (mesh_of_node() == kMixed) are always in the top, so a
  /// static mesh's subtree is never part of a moving subtree.
  template <class IsStatic>
  RefitPlan(const BvhTopology& bvh, const IsStatic& is_static, std::uint32_t min_subtree = 2048) {
    if (bvh.size() == 0) return;
    const std::uint32_t limit = std::max<std::uint32_t>(min_subtree, static_cast<std::uint32_t>(bvh.size() / 64));
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty()) {
      const std::uint32_t n = stack.back();
      stack.pop_back();
      if (is_static(n)) {
        static_roots_.push_back(n);
      } else if ((bvh.subtree_size(n) <= limit && bvh.mesh_of_node(n) != BvhTopology::kMixed) || bvh.leaf(n)) {
        roots_.push_back(n);
      } else {
        top_.push_back(n);
        stack.push_back(bvh.right(n));
        stack.push_back(bvh.left(n));
      }
    }
    std::sort(top_.begin(), top_.end());  // depth-first order: parents first
  }

  /// Refits `volumes` (one per node) from `leaf_volume(leaf node)`.
  template <class Volumes, class LeafVolume>
  void run(const BvhTopology& bvh, Volumes& volumes, const LeafVolume& leaf_volume) const {
    using BV = typename Volumes::value_type;
    if (roots_.size() == 1) {
      refit_range(bvh, volumes, roots_[0], bvh.nodes()[roots_[0]].end, leaf_volume);
    } else if (!roots_.empty()) {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, roots_.size(), 1),
          [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i)
              refit_range(bvh, volumes, roots_[i], bvh.nodes()[roots_[i]].end, leaf_volume);
          },
          tbb::static_partitioner());
    }
    for (auto it = top_.rbegin(); it != top_.rend(); ++it)
      volumes[*it] = BV::merged(volumes[bvh.left(*it)], volumes[bvh.right(*it)]);
  }

  /// Refits the static subtrees (once, at the start; the top is refitted by run()).
  template <class Volumes, class LeafVolume>
  void run_static(const BvhTopology& bvh, Volumes& volumes, const LeafVolume& leaf_volume) const {
    for (std::uint32_t r : static_roots_) refit_range(bvh, volumes, r, bvh.nodes()[r].end, leaf_volume);
  }

  std::size_t num_subtrees() const { return roots_.size(); }
  /// Nodes that run() refits: what one step's refit costs.
  std::size_t nodes_refitted(const BvhTopology& bvh) const {
    std::size_t n = top_.size();
    for (std::uint32_t r : roots_) n += bvh.subtree_size(r);
    return n;
  }

 private:
  std::vector<std::uint32_t> roots_;  ///< subtrees refitted in parallel
  std::vector<std::uint32_t> top_;    ///< inner nodes above them, ascending
  std::vector<std::uint32_t> static_roots_;  ///< subtrees that never move
};

}  // namespace mccd::detail
