#pragma once
/// @file Internal: the leaf representative rule, the default. Every vertex and every edge is
/// owned by the BVH leaf of its first (lowest id) triangle. A vertex-face pair (v, f) is then
/// tested at exactly one place: at the leaf pair {leaf owning v, leaf of f}, or inside one leaf
/// when both are the same; an edge-edge pair at the leaf pair of its two owners, or inside one
/// leaf. Both leaves contain the features' volumes, so whenever the features can meet, the
/// BVTT reaches that leaf pair. Unlike the canonical rule of the paper (core/carriers.h), a
/// leaf pair needs no search and adjacent leaves need no orphan set: they are ordinary front
/// nodes, and each leaf's own pairs are tested every step (Stepper's self stage).
///
/// At an overlapping leaf pair (A, B): the quarters in which the leaves meet (none: done);
/// each feature A owns against B's quarter volumes in those quarters, then each surviving
/// vertex against B's faces and each surviving edge against B's surviving edges, through
/// the common feature test (core/feature_tests.h) restricted to the quarters both survived in.
#include <cstdint>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/core/feature_tests.h>
#include <mccd/core/leaf_pieces.h>

namespace mccd::detail {

/// Which vertices and edges each BVH leaf owns (computed once from connectivity).
class LeafOwnership {
 public:
  static constexpr std::uint32_t kNoFace = 0xffffffffu;  ///< an isolated vertex has no owner

  LeafOwnership() = default;
  LeafOwnership(const BvhTopology& bvh, const MeshTopology& topo);

  /// The vertices / edges owned by BVH leaf node `node` (none for an inner node).
  const std::uint32_t* vertices_begin(std::uint32_t node) const { return vertices_.data() + vertex_begin_[node]; }
  const std::uint32_t* vertices_end(std::uint32_t node) const { return vertices_.data() + vertex_begin_[node + 1]; }
  const std::uint32_t* edges_begin(std::uint32_t node) const { return edges_.data() + edge_begin_[node]; }
  const std::uint32_t* edges_end(std::uint32_t node) const { return edges_.data() + edge_begin_[node + 1]; }

 private:
  std::vector<std::uint32_t> vertex_begin_, vertices_;  ///< CSR over BVH nodes
  std::vector<std::uint32_t> edge_begin_, edges_;
};

/// The feature pairs of leaf pairs and of single leaves under the leaf rule.
template <BoundingVolume BV, class NarrowPhase>
class OwnedPairs {
 public:
  using Quarters = QuarterVolume<BV>;
  /// A leaf owns at most 3 vertices and 3 edges per triangle.
  static constexpr unsigned kMaxOwned = 3 * BvhTopology::kMaxLeaf;

  OwnedPairs(const BvhTopology& bvh, const LeafOwnership& owners, const LeafPieces<BV>& pieces,
             const FeatureTests<BV, NarrowPhase>& tests)
      : bvh_(bvh), owners_(owners), pieces_(pieces), tests_(tests) {}

  /// Two different BVH leaves whose volumes overlap.
  void process(std::uint32_t a, std::uint32_t b, WorkerOutput& out) const {
    if (tests_.query().stopped()) return;
    ++out.stats.leaf_pairs;
    const unsigned within = pieces_.quarters(a, b);
    if (!within || tests_.too_late(within)) return;
    const Quarters& qa = pieces_.of(a);
    const Quarters& qb = pieces_.of(b);
    vertices_against(a, b, qb, within, out);
    vertices_against(b, a, qa, within, out);
    // Edges of each side that may meet the other leaf, with the quarters where they may.
    std::uint32_t ea[kMaxOwned], eb[kMaxOwned];
    unsigned ma[kMaxOwned], mb[kMaxOwned];
    const unsigned na = surviving_edges(a, qb, within, ea, ma);
    if (!na) return;
    const unsigned nb = surviving_edges(b, qa, within, eb, mb);
    const std::vector<Edge>& edges = tests_.topology().edges();
    for (unsigned i = 0; i < na; ++i) {
      const Edge& x = edges[ea[i]];
      for (unsigned j = 0; j < nb; ++j) {
        const unsigned m = ma[i] & mb[j];
        if (!m) continue;
        const Edge& y = edges[eb[j]];
        if (x[0] == y[0] || x[0] == y[1] || x[1] == y[0] || x[1] == y[1]) continue;
        tests_.test_ee(ea[i], eb[j], out, m);
      }
    }
  }

  /// The pairs inside one leaf: its owned vertices against its faces, its owned edges against
  /// each other.
  void process_self(std::uint32_t leaf, WorkerOutput& out) const {
    const std::uint32_t* faces = bvh_.leaf_triangles(leaf);
    const std::uint32_t nf = bvh_.leaf_count(leaf);
    const MeshTopology& topo = tests_.topology();
    for (const std::uint32_t* v = owners_.vertices_begin(leaf); v != owners_.vertices_end(leaf); ++v)
      for (std::uint32_t k = 0; k < nf; ++k) {
        const Triangle& t = topo.faces()[faces[k]];
        if (t[0] != *v && t[1] != *v && t[2] != *v) tests_.test_vf(*v, faces[k], out);
      }
    for (const std::uint32_t* a = owners_.edges_begin(leaf); a != owners_.edges_end(leaf); ++a) {
      const Edge& x = topo.edges()[*a];
      for (const std::uint32_t* b = a + 1; b != owners_.edges_end(leaf); ++b) {
        const Edge& y = topo.edges()[*b];
        if (x[0] == y[0] || x[0] == y[1] || x[1] == y[0] || x[1] == y[1]) continue;
        tests_.test_ee(*a, *b, out);
      }
    }
  }

 private:
  /// The vertices leaf `p` owns against the faces of leaf `q` (quarters `qq`).
  void vertices_against(std::uint32_t p, std::uint32_t q, const Quarters& qq, unsigned within,
                        WorkerOutput& out) const {
    const SweptVolumes<BV>& swept = tests_.swept();
    const MeshTopology& topo = tests_.topology();
    const std::uint32_t* faces = bvh_.leaf_triangles(q);
    const std::uint32_t nf = bvh_.leaf_count(q);
    Quarters face_quarters[BvhTopology::kMaxLeaf];
    unsigned merged = 0;  // bit k: face k's quarters merged
    for (const std::uint32_t* v = owners_.vertices_begin(p); v != owners_.vertices_end(p); ++v) {
      const unsigned m = swept.vertex_quarters(*v).overlap_mask(qq, within);
      if (!m) continue;
      for (std::uint32_t k = 0; k < nf; ++k) {
        const Triangle& t = topo.faces()[faces[k]];
        if (t[0] == *v || t[1] == *v || t[2] == *v) continue;
        ++out.stats.feature_box_tests;
        if (!swept.vertex(*v).overlaps(swept.face(faces[k]))) continue;
        if (!(merged >> k & 1u)) {
          face_quarters[k] = swept.face_quarters(t);
          merged |= 1u << k;
        }
        tests_.test_vf_quarters(*v, t, faces[k], face_quarters[k], out, m);
      }
    }
  }

  /// The edges leaf `p` owns that may meet quarters `qq` within `within`: ids and quarters.
  unsigned surviving_edges(std::uint32_t p, const Quarters& qq, unsigned within, std::uint32_t* ids,
                           unsigned* masks) const {
    const SweptVolumes<BV>& swept = tests_.swept();
    unsigned n = 0;
    for (const std::uint32_t* e = owners_.edges_begin(p); e != owners_.edges_end(p); ++e) {
      const unsigned m = swept.edge_quarters(*e).overlap_mask(qq, within);
      if (!m) continue;
      ids[n] = *e;
      masks[n++] = m;
    }
    return n;
  }

  const BvhTopology& bvh_;
  const LeafOwnership& owners_;
  const LeafPieces<BV>& pieces_;
  const FeatureTests<BV, NarrowPhase>& tests_;
};

}  // namespace mccd::detail
