#pragma once
/// @file Internal: stage 2 of a step (parallel/stepper.cpp), the refit: the BVH's node volumes
/// from the swept volumes, then the self-collision certificates (core/self_culling.h).
/// BVH refit as a static partition (paper section 4.7). The BVH never changes
/// shape, so its cut into subtrees of similar size is planned once; every step refits the
/// subtrees under a static partition (fixed work per subtree), then the few nodes above the
/// cut serially, deepest first. A BVH small enough to be one subtree is refitted serially,
/// without creating a task (Embree's bvh_refit does the same).
#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdint>
#include <vector>

#include <oneapi/tbb/partitioner.h>

#include <mccd/core/bvh.h>
#include <mccd/core/leaf_rule_owners.h>
#include <mccd/core/self_culling.h>
#include <mccd/core/stats.h>
#include <mccd/core/unchanged_leaves.h>
#include <mccd/geometry/assert.h>
#include <mccd/geometry/lane_masks.h>
#include <mccd/geometry/quarter_volumes.h>
#include <mccd/geometry/swept_volumes.h>
#include <mccd/parallel/tbb_executor.h>

namespace mccd::detail {

class RefitPlan {
 public:
  RefitPlan() = default;
  /// Cuts the BVH into subtrees of at most ~1/1024 of the nodes, and at least `min_subtree`
  /// nodes so that tiny scenes stay one piece (a large BVH gives 16 threads 64 subtrees each,
  /// a 4K-triangle one a few each: a static partition of a few large subtrees left threads
  /// idle, and a 16-thread refit of such a scene ran at the speed of one thread). Subtrees whose triangles never move
  /// (`is_static(node)`) are set apart: refitted once by run_static(), never by run().
  /// Nodes above the meshes' subtrees (mesh_of_node() == kMixed) are always in the top, so a
  /// static mesh's subtree is never part of a moving subtree.
  template <class IsStatic>
  RefitPlan(const BvhTopology& bvh, const IsStatic& is_static, std::uint32_t min_subtree = 64) {
    if (bvh.size() == 0) return;
    const std::uint32_t limit = std::max<std::uint32_t>(min_subtree, static_cast<std::uint32_t>(bvh.size() / 1024));
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
      for_each_index(
          roots_.size(),
          [&](std::size_t i) { refit_range(bvh, volumes, roots_[i], bvh.nodes()[roots_[i]].end, leaf_volume); },
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

/// A leaf's quarter volumes: the merge of its corners' (owned, then the others'), each once.
template <BoundingVolume BV>
QuarterVolume<BV> leaf_volume(const LeafOwnership& owners, const SweptVolumes<BV>& swept, std::uint32_t node) {
  // The other corners lie elsewhere in the storage: asked for first, merged after the leaf's
  // own vertices (which lie together).
  for (std::uint32_t i = owners.foreign_begin(node); i != owners.foreign_begin(node + 1); ++i) {
    const char* p = reinterpret_cast<const char*>(&swept.vertex_quarters_at(owners.foreign_corner(i)));
    for (std::size_t line = 0; line < sizeof(QuarterVolume<BV>); line += 64) __builtin_prefetch(p + line);
  }
  QuarterVolume<BV> v = QuarterVolume<BV>::empty();
  const std::uint32_t vb = owners.vertex_begin(node), fb = owners.foreign_begin(node);
  if constexpr (BV::kSlabs == 9) {
    // in vector lanes where the processor has them (LaneKernels::merge_quarters: the same bits)
    if (const auto merge = lane_kernels().merge_quarters) {
      const auto* base = reinterpret_cast<const float*>(&swept.vertex_quarters_at(0));
      float* acc = v.bounds[0][0];
      merge(base + 72 * std::size_t(vb), nullptr, owners.vertex_begin(node + 1) - vb, acc);
      merge(base, owners.foreign_corners_from(fb), owners.foreign_begin(node + 1) - fb, acc);
      return v;
    }
  }
  v.merge_each(owners.vertex_begin(node + 1) - vb, [&](std::uint32_t i) -> const QuarterVolume<BV>& {
    return swept.vertex_quarters_at(vb + i);
  });
  v.merge_each(owners.foreign_begin(node + 1) - fb, [&](std::uint32_t i) -> const QuarterVolume<BV>& {
    return swept.vertex_quarters_at(owners.foreign_corner(fb + i));
  });
  return v;
}

/// Whether the ray from `o` along `d` may meet the first quarter's box of `v` (false only when
/// it certainly does not: the box is grown by 2^-30 of the largest magnitude involved, far
/// more than the relative error 2^-51 of each slab's parameters).
template <class Quarters>
bool ray_meets_box(const Quarters& v, const Vec3& o, const Vec3& d) {
  double enter = 0, leave = std::numeric_limits<double>::infinity();
  for (int s = 0; s < 3; ++s) {
    const double lo0 = v.lo(s)[0], hi0 = v.hi(s)[0];
    if (!(lo0 <= hi0)) return true;  // empty or NaN: no claim
    const double grow = 0x1p-30 * std::max({std::abs(lo0), std::abs(hi0), std::abs(o[s])}) + 0x1p-1000;
    const double lo = lo0 - grow, hi = hi0 + grow;
    if (d[s] == 0) {
      if (o[s] < lo || o[s] > hi) return false;
      continue;
    }
    double a = (lo - o[s]) / d[s], b = (hi - o[s]) / d[s];
    if (a > b) std::swap(a, b);
    enter = std::max(enter, a);
    leave = std::min(leave, b);
  }
  return !(enter > leave);
}

/// Stage 2: every node volume from the swept volumes (a leaf whose corners all repeat the
/// previous full step keeps its volume when `unchanged` is active), then, with `cull`, the
/// patches certified free of self-collision for x0 -> x1 (cleared otherwise).
template <BoundingVolume BV>
void refit_stage(const RefitPlan& plan, const BvhTopology& bvh, const LeafOwnership& owners,
                 const SweptVolumes<BV>& swept, UnchangedLeaves& unchanged, LargeVector<QuarterVolume<BV>>& nodes,
                 bool cull, SelfCulling& culling, const MeshTopology& topo, const Positions& x0, const Positions& x1,
                 StepStats& stats) {
  MCCD_ASSERT(nodes.size() == bvh.size(), "node volumes not sized to the BVH");
  if (unchanged.active())
    plan.run(bvh, nodes, [&](std::uint32_t n) {
      return unchanged.mark_leaf(n, owners) ? nodes[n] : leaf_volume(owners, swept, n);
    });
  else
    plan.run(bvh, nodes, [&](std::uint32_t n) { return leaf_volume(owners, swept, n); });
  stats.refit_nodes = plan.nodes_refitted(bvh);
  if (cull && culling.possible()) {
    // A closed surface whose leaves all repeat the previous full step keeps its certificate
    // from then (the previous full step certified too: it was not brute force).
    SelfCulling::Repeats repeats;
    if (unchanged.active()) repeats = [&](std::uint32_t n) { return unchanged.subtree_repeats(n, bvh); };
    // A node's first-quarter box holds its triangles at the start of the step; the ray test
    // grows it by far more than the rounding of its double arithmetic before it rules a node
    // out.
    culling.certify(
        bvh, topo, x0, x1, tbb_executor(),
        [&](std::uint32_t n, const Vec3& o, const Vec3& d) { return ray_meets_box(nodes[n], o, d); },
        owners.face_corners_in_order(), repeats);
    stats.culled_patches = culling.certified();
  } else {
    culling.clear();
  }
}

}  // namespace mccd::detail
