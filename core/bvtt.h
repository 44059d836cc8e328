#pragma once
/// @file Internal: the bounding volume test tree (BVTT), walked without being stored. A pair
/// node (a, b), a != b, tests the volumes of BVH nodes a and b; its children split the larger
/// (or the non-leaf) of the two. A self node (n, n) stands for collisions inside n: for an
/// inner n it has three children, (l, l), (r, r) and (l, r); a leaf self node is empty. The
/// front (core/front.h) is the set of pair nodes where a traversal stopped: disjoint pairs
/// and leaf pairs. Under the canonical representative rule, leaf pairs of adjacent triangles
/// only stop without a test and are never in the front: their features are the orphan set's
/// (core/canonical_rule_orphans.h). Pairs inside one leaf are the self stage's (core/leaf_pairs.h).
///
/// Self-collision culling (core/self_culling.h): a self node of a node certified this step, or
/// under one, stops without a test; the front keeps it, and a front node whose two nodes lie
/// under one certified node stays in the front untested. A kept self node that is no longer
/// covered is expanded like an overlapping front node.
#include <algorithm>
#include <cstdint>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/core/bvtt_node.h>
#include <mccd/core/query.h>
#include <mccd/core/scene_topology.h>
#include <mccd/core/self_culling.h>
#include <mccd/core/worker_output.h>
#include <mccd/geometry/large_allocator.h>
#include <mccd/geometry/kdop.h>
#include <mccd/geometry/topology.h>

namespace mccd::detail {

/// Walks the BVTT over a BVH and its node volumes; `Leaf` processes overlapping leaf pairs
/// (core/leaf_pairs.h). Stateless between calls; every call writes only to the WorkerOutput
/// it is given.
///
/// Node volumes are quarter volumes (geometry/quarter_volumes.h): two nodes overlap when they
/// overlap in some quarter of the step, the quarters where they do go down to the leaf pair.
/// A feature's quarter volumes lie inside those of every node above it, quarter by quarter,
/// so every pair of features that can meet still reaches its leaf pair, and node pairs that
/// overlap only over the whole step but in no common quarter stop early.
template <class NodeVolume, class Leaf>
class Bvtt {
 public:
  /// `culling`: the step's self-collision certificates (nullptr: none).
  Bvtt(const BvhTopology& bvh, const LargeVector<NodeVolume>& volumes, const SceneTopology& scene, const Leaf& leaf,
       const QueryState& query, const SelfCulling* culling = nullptr)
      : bvh_(bvh), volumes_(volumes), scene_(scene), leaf_(leaf), query_(query), culling_(culling) {}

  const BvhTopology& bvh() const { return bvh_; }

  /// One node: a self node yields its three children; a pair node is tested and either stops
  /// (recorded in out.front with `record`) or yields its two children into `next`.
  template <bool record>
  void visit(const NodePair n, WorkerOutput& out, std::vector<NodePair>& next) const {
    if (scene_.has_skipped_pairs() && skipped(n)) return;
    if (n.a == n.b) {
      if (bvh_.leaf(n.a)) return;  // pairs inside one leaf: the self stage's
      if (culling_ && culling_->covered(n.a)) {
        ++out.stats.culled_nodes;
        if constexpr (record) out.front.push_back(n);
        return;
      }
      const std::uint32_t l = bvh_.left(n.a), r = bvh_.right(n.a);
      next.push_back({l, r});
      next.push_back({r, r});
      next.push_back({l, l});
      return;
    }
    if (bvh_.leaf(n.a) && bvh_.leaf(n.b)) {
      if (leaf_.skips(n.a, n.b)) {
        ++out.stats.adjacent_leaf_pairs;
        return;
      }
      if constexpr (record) out.front.push_back(n);
      ++out.stats.volume_tests;
      if (const unsigned q = quarters(n)) leaf_.process(n.a, n.b, q, out);
      return;
    }
    ++out.stats.volume_tests;
    if (!quarters(n)) {
      if constexpr (record) out.front.push_back(n);
      return;
    }
    push_children(n, next);
  }

  /// Work of a visit in the units of traverse()'s budget: a node test 1, a leaf pair (its
  /// feature pairs and elementary tests) kLeafPairWork. traverse() counts a leaf pair's
  /// feature pairs too (WorkerOutput::pair_work(), kPairsPerUnit of them a unit): a contact
  /// region's costly leaf pairs then split a task sooner, and no task holds many of them.
  static constexpr std::size_t kLeafPairWork = 16, kPairsPerUnit = 8;
  /// The work of visiting `n`, in those units.
  std::size_t work_of(const NodePair& n) const { return bvh_.leaf(n.a) && bvh_.leaf(n.b) ? kLeafPairWork : 1; }

  /// Depth-first traversal of everything on out.stack (its leaf pairs processed by the time
  /// it returns), or until it has done `budget` units of work (kLeafPairWork): the rest is
  /// left on out.stack, the larger subtrees deepest (parallel/phc.h hands them to tasks of
  /// their own). Returns the work done (at least `budget` when it stopped for it).
  template <bool record>
  std::size_t traverse(WorkerOutput& out, std::size_t budget = static_cast<std::size_t>(-1)) const {
    auto& st = out.stack;
    std::size_t work = 0;
    while (!st.empty() && work < budget) {
      if (query_.stopped()) {
        st.clear();
        break;
      }
      const NodePair n = st.back();
      st.pop_back();
      if (bvh_.leaf(n.a) && bvh_.leaf(n.b)) {
        // a leaf pair: at least kLeafPairWork, more where it tested and queued many feature
        // pairs (counts, so the split is the same on every run and thread count)
        const std::uint64_t before = out.pair_work();
        const std::size_t stops = out.front.size();
        visit<record>(n, out, st);
        const std::uint64_t done = out.pair_work() - before;
        work += std::max<std::size_t>(kLeafPairWork, static_cast<std::size_t>(done / kPairsPerUnit));
        // recorded as the next front's stop: noted for its cuts when costly
        if constexpr (record)
          if (out.front.size() != stops) out.note_leaf_pair(stops, done);
      } else {
        ++work;
        visit<record>(n, out, st);
      }
    }
    finish(out);
    return work;
  }

  /// Processes what the leaf pairs visit() found left queued in `out` (Leaf::finish). Every
  /// entry point but visit() calls it before returning.
  void finish(WorkerOutput& out) const { leaf_.finish(out); }

  /// Children of an inner pair node: split the non-leaf, or the larger, of the two.
  void push_children(const NodePair& n, std::vector<NodePair>& st) const {
    const bool split_b = bvh_.leaf(n.a) || (!bvh_.leaf(n.b) && bvh_.subtree_size(n.b) > bvh_.subtree_size(n.a));
    if (split_b) {
      st.push_back({n.a, bvh_.right(n.b)});
      st.push_back({n.a, bvh_.left(n.b)});
    } else {
      st.push_back({bvh_.right(n.a), n.b});
      st.push_back({bvh_.left(n.a), n.b});
    }
  }

  /// Whether front node n is covered by a patch certified this step (counted).
  bool culled(const NodePair& n, WorkerOutput& out) const {
    if (!culling_ || !(n.a == n.b ? culling_->covered(n.a) : culling_->covers(n.a, n.b))) return false;
    ++out.stats.culled_nodes;
    return true;
  }

  /// The quarters of the step in which the volumes of the pair's two nodes overlap.
  [[gnu::always_inline]] unsigned quarters(const NodePair& n) const {
    return volumes_[n.a].overlap_mask(volumes_[n.b]);
  }

  /// Asks for the volumes quarters(n) reads (their box slabs, where most tests end).
  void prefetch(const NodePair& n) const {
    __builtin_prefetch(&volumes_[n.a]);
    __builtin_prefetch(reinterpret_cast<const char*>(&volumes_[n.a]) + 64);
    __builtin_prefetch(&volumes_[n.b]);
    __builtin_prefetch(reinterpret_cast<const char*>(&volumes_[n.b]) + 64);
  }

  const Leaf& leaf() const { return leaf_; }
  /// Whether the query has its answer (no more node needs a visit).
  bool stopped() const { return query_.stopped(); }

 private:
  /// Pairs below two nodes of single meshes that are never tested (a static mesh, or one
  /// without self-collision): the whole BVTT subtree is skipped, never entering the front.
  bool skipped(const NodePair& n) const {
    const std::uint32_t ma = bvh_.mesh_of_node(n.a), mb = bvh_.mesh_of_node(n.b);
    return ma != BvhTopology::kMixed && mb != BvhTopology::kMixed && scene_.skips(ma, mb);
  }

  const BvhTopology& bvh_;
  const LargeVector<NodeVolume>& volumes_;
  const SceneTopology& scene_;
  const Leaf& leaf_;
  const QueryState& query_;
  const SelfCulling* culling_;
};

}  // namespace mccd::detail
