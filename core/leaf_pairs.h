#pragma once
/// @file Internal: the work at an overlapping pair of BVH leaves and inside single leaves, under
/// the scene's representative rule (SceneOptions::representatives): the leaf rule
/// (core/leaf_rule_owners.h, the default) or the paper's canonical rule with its orphan set
/// (core/canonical_rule_pairs.h). Either way each feature pair goes through the same test
/// (core/feature_tests.h) at exactly one place per step, so both rules and every method report
/// identical contacts. The rule is chosen once per scene; one branch per leaf pair.
#include <cstdint>
#include <utility>
#include <vector>

#include <mccd/core/canonical_rule_pairs.h>
#include <mccd/core/leaf_lanes.h>
#include <mccd/core/leaf_rule_owners.h>
#include <mccd/core/leaf_rule_pairs.h>
#include <mccd/core/canonical_rule_orphans.h>
#include <mccd/core/scene_topology.h>
#include <mccd/core/self_culling.h>

namespace mccd::detail {

template <BoundingVolume BV, class NarrowPhase = ConservativeCcd>
class LeafPairs {
 public:
  using Tests = FeatureTests<BV, NarrowPhase>;

  using Quarters = QuarterVolume<BV>;

  /// `bvh`, `owners`, `nodes` (the BVH nodes' quarter volumes), `lanes` (the leaves' lane
  /// blocks, leaf rule), `tests` and `unchanged`
  /// (leaves that repeat the previous step, leaf rule; nullptr: none) and `culling` (the step's
  /// self-collision certificates; nullptr: none) are owned by the caller and outlive this
  /// object.
  LeafPairs(const SceneTopology& scene, const BvhTopology& bvh, const LeafOwnership& owners,
            const LargeVector<Quarters>& nodes, const LeafLanes<BV>& lanes, const Tests& tests,
            const UnchangedLeaves* unchanged = nullptr,
            const SelfCulling* culling = nullptr)
      : scene_(scene),
        tests_(tests),
        culling_(culling),
        owned_rule_(scene.representatives() == Representatives::Leaf),
        owned_(bvh, owners, nodes, lanes, tests, unchanged),
        canonical_(bvh, scene.carriers(), nodes, tests) {
    const MeshTopology& topo = scene.topology();
    for (std::uint32_t i = 0; i < bvh.size(); ++i) {
      if (!bvh.leaf(i)) continue;
      const std::uint32_t m = bvh.mesh_of_node(i);
      if (m != BvhTopology::kMixed && scene.skips(m, m)) continue;  // its own pairs are never tested
      if (owned_rule_) {
        self_leaves_.push_back(i);
        continue;
      }
      const std::uint32_t* t = bvh.leaf_triangles(i);
      for (std::uint32_t a = 0; a < bvh.leaf_count(i); ++a)
        for (std::uint32_t b = a + 1; b < bvh.leaf_count(i); ++b)
          if (!topo.adjacent(t[a], t[b])) leaf_internal_.emplace_back(t[a], t[b]);
    }
  }

  const Tests& tests() const { return tests_; }

  /// Whether the BVTT skips the leaf pair (a, b) without a volume test (canonical rule: every
  /// triangle pair adjacent, so every feature pair is an orphan's).
  bool skips(std::uint32_t a, std::uint32_t b) const { return !owned_rule_ && canonical_.all_adjacent(a, b); }

  /// Two different BVH leaves whose quarter volumes overlap in the quarters `within`.
  void process(std::uint32_t a, std::uint32_t b, unsigned within, WorkerOutput& out) const {
    if (owned_rule_)
      owned_.process(a, b, within, out);
    else
      canonical_.process(a, b, within, out);
  }

  /// Processes what process() left queued in `out` (the leaf rule's narrow phase runs queued
  /// pairs together: core/leaf_rule_pairs.h).
  void finish(WorkerOutput& out) const {
    if (owned_rule_) owned_.finish(out);
  }

  /// The units of the self stage (the pairs that no BVTT pair node holds), each independent:
  /// leaf rule, one per leaf of a mesh with self-collision; canonical rule, one.
  std::size_t num_self_units() const { return owned_rule_ ? self_leaves_.size() : 1; }
  /// Self units [begin, end): leaf rule, each leaf's own pairs; canonical, the orphan set and
  /// the non-adjacent triangle pairs inside each leaf.
  void process_self(std::size_t begin, std::size_t end, WorkerOutput& out) const {
    if (owned_rule_) {
      for (std::size_t i = begin; i != end; ++i) {
        if (culling_ && culling_->covered(self_leaves_[i]))
          ++out.stats.culled_nodes;  // certified to hold no self-collision this step
        else
          owned_.process_self(self_leaves_[i], out);
      }
      owned_.finish(out);
      return;
    }
    if (begin == end) return;
    test_orphans(scene_.orphans(), tests_, out);
    for (const auto& [s, t] : leaf_internal_) canonical_.process_if_overlapping(s, t, out);
  }

 private:
  const SceneTopology& scene_;
  const Tests& tests_;
  const SelfCulling* culling_;
  bool owned_rule_;
  OwnedPairs<BV, NarrowPhase> owned_;
  CanonicalPairs<BV, NarrowPhase> canonical_;
  std::vector<std::uint32_t> self_leaves_;  ///< leaf rule: the leaves whose own pairs are tested
  /// Canonical rule: non-adjacent triangle pairs inside one BVH leaf.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> leaf_internal_;
};

}  // namespace mccd::detail
