#pragma once
/// @file Internal: the canonical representative rule, which non-adjacent triangle pair carries
/// each vertex-face and edge-edge test (paper section 4.6, DESIGN "Representative features").
///
/// What must be tested in a step: every (v, f) with v not a corner of f, and every pair of
/// edges that share no vertex. If such a pair collides, the contact point lies in the swept
/// volume of every triangle around each feature, so every triangle pair around it overlaps.
///
/// Canonical rule. A VF pair (v, f) is carried by the non-adjacent triangle pair (s, f) where
/// s is the first (lowest id) triangle around v not adjacent to f. An EE pair (a, b), a < b,
/// is carried by the lexicographically first (s, t) in faces(a) x faces(b) with s not
/// adjacent to t. Each feature pair thus has at most one carrier; the pairs with none (every
/// candidate triangle pair is adjacent) form the orphan set (core/canonical_rule_orphans.h).
#include <cstdint>
#include <utility>
#include <vector>

#include <mccd/geometry/topology.h>

namespace mccd::detail {

class Carriers {
 public:
  /// Per triangle, the first (lowest) face around each of its corners and each of its edges
  /// (edge k joins corners k and k + 1), laid out together so that a leaf pair reads its two
  /// triangles' records and nothing else on the common paths of the rule.
  struct TriangleFirsts {
    std::uint32_t corner[3];
    std::uint32_t edge[3];
  };

  Carriers() = default;
  explicit Carriers(const MeshTopology& topo);

  const TriangleFirsts& firsts(std::uint32_t f) const { return firsts_[f]; }

  /// carries_vf with the first face f0 of v already known (s's record): true when f0 is s; else
  /// false unless f0 is adjacent to t, when the faces around v are searched.
  bool carries_vf(std::uint32_t v, std::uint32_t f0, std::uint32_t s, std::uint32_t t) const {
    if (f0 == s) return true;
    if (!topo_->adjacent(f0, t)) return false;
    return carries_vf(v, s, t);
  }

  /// carries_ee with the first faces fa of a and fb of b already known.
  bool carries_ee(std::uint32_t a, std::uint32_t fa, std::uint32_t s, std::uint32_t b, std::uint32_t fb,
                  std::uint32_t t) const {
    if (fa == s && fb == t) return true;
    if (!topo_->adjacent(fa, fb)) return false;
    return carries_ee(a, s, b, t);
  }

  /// Whether the leaf pair (s, t) (non-adjacent) carries the VF pair (v, t), v a corner of s.
  bool carries_vf(std::uint32_t v, std::uint32_t s, std::uint32_t t) const {
    const std::uint32_t f0 = first_face_[v];  // fast paths: the first face is the carrier
    if (f0 == s) return true;                 // (s is not adjacent to t)
    if (!topo_->adjacent(f0, t)) return false;
    for (auto* f = topo_->vertex_faces_begin(v); f != topo_->vertex_faces_end(v); ++f)
      if (!topo_->adjacent(*f, t)) return *f == s;
    return false;
  }

  /// Whether the non-adjacent leaf pair (s, t) carries the EE pair (a, b), a an edge of s and
  /// b an edge of t.
  bool carries_ee(std::uint32_t a, std::uint32_t s, std::uint32_t b, std::uint32_t t) const {
    if (a > b) {
      std::swap(a, b);
      std::swap(s, t);
    }
    const std::uint32_t fa = first_face_of_edge_[a], fb = first_face_of_edge_[b];
    if (fa == s && fb == t) return true;  // fast paths: the first pair
    if (!topo_->adjacent(fa, fb)) return false;
    for (auto* f = topo_->edge_faces_begin(a); f != topo_->edge_faces_end(a); ++f)
      for (auto* g = topo_->edge_faces_begin(b); g != topo_->edge_faces_end(b); ++g)
        if (!topo_->adjacent(*f, *g)) return *f == s && *g == t;
    return false;
  }

 private:
  const MeshTopology* topo_ = nullptr;
  std::vector<std::uint32_t> first_face_;          ///< lowest face around each vertex
  std::vector<std::uint32_t> first_face_of_edge_;  ///< lowest face around each edge
  std::vector<TriangleFirsts> firsts_;
};

}  // namespace mccd::detail
