#pragma once
/// @file Internal: the orphan set (paper section 4.6), the feature pairs whose only candidate
/// carriers are adjacent triangle pairs, which the BVTT front never holds. Computed once from
/// connectivity; tested every step behind the same feature-volume tests as every other pair.
#include <cstdint>
#include <algorithm>
#include <utility>
#include <vector>

#include <mccd/geometry/topology.h>

namespace mccd::detail {

class OrphanSet {
 public:
  OrphanSet() = default;
  explicit OrphanSet(const MeshTopology& topo);
  /// Orphan VF pairs (vertex, face), sorted.
  const std::vector<std::pair<std::uint32_t, std::uint32_t>>& vf() const { return vf_; }
  /// Orphan EE pairs (edge a, edge b), a < b, sorted.
  const std::vector<std::pair<std::uint32_t, std::uint32_t>>& ee() const { return ee_; }

  /// Drops the pairs inside meshes whose own pairs are never tested: an orphan pair lies in
  /// one connected piece, so `skip_face(f)` of any face of it decides (VF: the face; EE: the
  /// first face of edge a).
  template <class SkipFace>
  void drop_if(const SkipFace& skip_face, const MeshTopology& topo) {
    std::erase_if(vf_, [&](const auto& p) { return skip_face(p.second); });
    std::erase_if(ee_, [&](const auto& p) { return skip_face(*topo.edge_faces_begin(p.first)); });
  }

 private:
  std::vector<std::pair<std::uint32_t, std::uint32_t>> vf_, ee_;
};

/// The orphan tests of one step: every orphan pair through `leaf_pairs` (core/leaf_pairs.h),
/// counted apart in the statistics.
template <class LeafPairs, class Output>
void test_orphans(const OrphanSet& orphans, const LeafPairs& leaf_pairs, Output& out) {
  const std::uint64_t vf0 = out.stats.vf_tests, ee0 = out.stats.ee_tests;
  for (const auto& [v, f] : orphans.vf()) leaf_pairs.test_vf(v, f, out);
  for (const auto& [a, b] : orphans.ee()) leaf_pairs.test_ee(a, b, out);
  out.stats.orphan_vf_tested += out.stats.vf_tests - vf0;
  out.stats.orphan_ee_tested += out.stats.ee_tests - ee0;
}

/// For comparison only: the orphan set sizes a *static* representative rule would give, where
/// each vertex and each edge is assigned to its first (lowest id) incident triangle and a pair
/// is tested by the pair of assigned triangles unless those are adjacent.
struct StaticOrphanCounts {
  std::size_t vf = 0, ee = 0;
};
StaticOrphanCounts static_orphan_counts(const MeshTopology& topo);

}  // namespace mccd::detail
