#pragma once
/// @file Internal: the canonical representative rule of the paper (section 4.6) at a leaf pair:
/// each non-adjacent pair of the leaves' triangles tests the feature pairs it carries
/// (core/canonical_rule_carriers.h), behind the triangles' volume tests, through the common feature test
/// (core/feature_tests.h). Adjacent triangle pairs carry nothing: their feature pairs are the
/// orphan set's (core/canonical_rule_orphans.h), and leaf pairs of adjacent triangles only never enter the
/// front. Selected with SceneOptions::representatives = Canonical (the paper's setting, the
/// default with the paper's median BVH).
#include <cstdint>

#include <mccd/core/bvh.h>
#include <mccd/core/canonical_rule_carriers.h>
#include <mccd/core/feature_tests.h>

namespace mccd::detail {

template <BoundingVolume BV, class NarrowPhase>
class CanonicalPairs {
 public:
  using Quarters = QuarterVolume<BV>;

  /// `nodes`: the quarter volumes of the BVH nodes.
  CanonicalPairs(const BvhTopology& bvh, const Carriers& carriers, const LargeVector<Quarters>& nodes,
                 const FeatureTests<BV, NarrowPhase>& tests)
      : bvh_(bvh), carriers_(carriers), nodes_(nodes), tests_(tests) {}

  /// Whether every triangle of leaf a is adjacent to every triangle of leaf b: their features
  /// are all the orphan set's, so the leaf pair is skipped without a test.
  bool all_adjacent(std::uint32_t a, std::uint32_t b) const {
    const std::uint32_t *ta = bvh_.leaf_triangles(a), *tb = bvh_.leaf_triangles(b);
    for (std::uint32_t i = 0; i < bvh_.leaf_count(a); ++i)
      for (std::uint32_t j = 0; j < bvh_.leaf_count(b); ++j)
        if (!tests_.topology().adjacent(ta[i], tb[j])) return false;
    return true;
  }

  /// Two BVH leaves that meet in the quarters `within`: each non-adjacent pair of their
  /// triangles, behind the triangles' own volume test (skipped with one triangle per leaf,
  /// where the leaf volumes are the triangle volumes).
  void process(std::uint32_t a, std::uint32_t b, unsigned within, WorkerOutput& out) const {
    const std::uint32_t na = bvh_.leaf_count(a), nb = bvh_.leaf_count(b);
    const std::uint32_t *ta = bvh_.leaf_triangles(a), *tb = bvh_.leaf_triangles(b);
    if (na == 1 && nb == 1) {
      triangles(ta[0], tb[0], nodes_[a], nodes_[b], within, out);  // not adjacent: see all_adjacent
      return;
    }
    if (tests_.too_late(within)) return;
    Quarters qa[BvhTopology::kMaxLeaf], qb[BvhTopology::kMaxLeaf];
    unsigned merged_a = 0, merged_b = 0;
    const SweptVolumes<BV>& swept = tests_.swept();
    const MeshTopology& topo = tests_.topology();
    for (std::uint32_t i = 0; i < na; ++i)
      for (std::uint32_t j = 0; j < nb; ++j) {
        if (topo.adjacent(ta[i], tb[j])) continue;
        ++out.stats.triangle_tests;
        if (!swept.face(ta[i]).overlaps(swept.face(tb[j]))) continue;
        if (!(merged_a >> i & 1u)) qa[i] = swept.face_quarters(topo.faces()[ta[i]]), merged_a |= 1u << i;
        if (!(merged_b >> j & 1u)) qb[j] = swept.face_quarters(topo.faces()[tb[j]]), merged_b |= 1u << j;
        triangles(ta[i], tb[j], qa[i], qb[j], within, out);
      }
  }

  /// The non-adjacent triangle pair (s, t) if their volumes overlap (adjacent pairs are
  /// skipped): a pair inside one leaf.
  void process_if_overlapping(std::uint32_t s, std::uint32_t t, WorkerOutput& out) const {
    const MeshTopology& topo = tests_.topology();
    if (topo.adjacent(s, t)) return;
    ++out.stats.triangle_tests;
    const SweptVolumes<BV>& swept = tests_.swept();
    if (swept.face(s).overlaps(swept.face(t)))
      triangles(s, t, swept.face_quarters(topo.faces()[s]), swept.face_quarters(topo.faces()[t]), 0xF, out);
  }

 private:
  /// The feature pairs carried by the non-adjacent, overlapping triangle pair (s, t), with the
  /// triangles' quarters; `within` as for FeatureTests.
  void triangles(std::uint32_t s, std::uint32_t t, const Quarters& qs, const Quarters& qt, unsigned within,
                 WorkerOutput& out) const {
    ++out.stats.leaf_pairs;
    // Every feature of s and t lies in its triangle during each quarter: when the triangles'
    // quarter volumes never meet, no feature pair below can pass its own test.
    const unsigned quarters = qs.overlap_mask(qt, within);
    if (!quarters || tests_.too_late(quarters)) return;
    const MeshTopology& topo = tests_.topology();
    const Triangle& S = topo.faces()[s];
    const Triangle& T = topo.faces()[t];
    const Carriers::TriangleFirsts& fs = carriers_.firsts(s);
    const Carriers::TriangleFirsts& ft = carriers_.firsts(t);
    for (int k = 0; k < 3; ++k)
      if (carriers_.carries_vf(S[k], fs.corner[k], s, t)) vf(S[k], T, t, qt, quarters, out);
    for (int k = 0; k < 3; ++k)
      if (carriers_.carries_vf(T[k], ft.corner[k], t, s)) vf(T[k], S, s, qs, quarters, out);
    const auto& es = topo.face_edges(s);
    const auto& et = topo.face_edges(t);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (carriers_.carries_ee(es[i], fs.edge[i], s, et[j], ft.edge[j], t)) tests_.test_ee(es[i], et[j], out, quarters);
  }

  void vf(std::uint32_t v, const Triangle& t, std::uint32_t f, const Quarters& qf, unsigned within,
          WorkerOutput& out) const {
    if (tests_.query().stopped()) return;
    ++out.stats.feature_box_tests;
    if (!tests_.swept().vertex(v).overlaps(tests_.swept().face(f))) return;
    tests_.test_vf_quarters(v, tests_.swept().vertex_quarters(v), t, f, qf, out, within);
  }

  const BvhTopology& bvh_;
  const Carriers& carriers_;
  const LargeVector<Quarters>& nodes_;
  const FeatureTests<BV, NarrowPhase>& tests_;
};

}  // namespace mccd::detail
