#pragma once
/// @file Internal: the leaf representative rule, the default. Every vertex and every edge is
/// owned by the BVH leaf of its first (lowest id) triangle. A vertex-face pair (v, f) is then
/// tested at exactly one place: at the leaf pair {leaf owning v, leaf of f}, or inside one leaf
/// when both are the same; an edge-edge pair at the leaf pair of its two owners, or inside one
/// leaf. Both leaves contain the features' volumes, so whenever the features can meet, the
/// BVTT reaches that leaf pair. Unlike the canonical rule of the paper (core/canonical_rule_carriers.h), a
/// leaf pair needs no search and adjacent leaves need no orphan set: they are ordinary front
/// nodes, and each leaf's own pairs are tested every step (Stepper's self stage).
/// The leaf pairs' work under this rule is core/leaf_rule_pairs.h.
#include <bit>
#include <cstdint>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/core/executor.h>
#include <mccd/core/feature_tests.h>
#include <mccd/core/unchanged_leaves.h>

namespace mccd::detail {

/// Whether two edges share an end, and whether a vertex is a corner of a triangle (no branch:
/// every comparison).
inline bool shares_end(const Edge& x, const Edge& y) {
  return int(x[0] == y[0]) | int(x[0] == y[1]) | int(x[1] == y[0]) | int(x[1] == y[1]);
}
inline bool has_corner(const Triangle& t, std::uint32_t v) { return int(t[0] == v) | int(t[1] == v) | int(t[2] == v); }

/// Which vertices and edges each BVH leaf owns (computed once from connectivity).
class LeafOwnership {
 public:
  static constexpr std::uint32_t kNoFace = 0xffffffffu;  ///< an isolated vertex has no owner

  LeafOwnership() = default;
  /// Fills its tables through `ex` (the same tables on any executor).
  LeafOwnership(const BvhTopology& bvh, const MeshTopology& topo, const Executor& ex = serial_executor());

  /// The vertices / edges owned by BVH leaf node `node` (none for an inner node): slots
  /// [vertex_begin(node), vertex_begin(node + 1)) of vertex(slot), likewise for edges. The
  /// slots are the storage layout of the swept volumes (layout()).
  std::uint32_t vertex_begin(std::uint32_t node) const { return vertex_begin_[node]; }
  std::uint32_t edge_begin(std::uint32_t node) const { return edge_begin_[node]; }
  std::uint32_t vertex(std::uint32_t slot) const { return vertices_[slot]; }
  std::uint32_t edge(std::uint32_t slot) const { return edges_[slot]; }
  /// The corners of leaf `node`'s triangles that other leaves own, as vertex slots
  /// [foreign_begin(node), foreign_begin(node + 1)) of foreign_corner(i), each once: with the
  /// leaf's own vertices, every corner of the leaf exactly once (what its refit merges).
  std::uint32_t foreign_begin(std::uint32_t node) const { return foreign_begin_[node]; }
  std::uint32_t foreign_corner(std::uint32_t i) const { return foreign_[i]; }
  /// foreign_corner(i), foreign_corner(i + 1), ... in a row.
  const std::uint32_t* foreign_corners_from(std::uint32_t i) const { return foreign_.data() + i; }
  /// The vertex ids of the edge in `slot`.
  const Edge& edge_ends(std::uint32_t slot) const { return edge_ends_[slot]; }
  /// edge(), edge_ends() and face_corners() from `slot` on, as arrays (a leaf's, read in a loop
  /// through a pointer held in a register; `slot` may be one past the last).
  const std::uint32_t* edges_from(std::uint32_t slot) const { return edges_.data() + slot; }
  const Edge* edge_ends_from(std::uint32_t slot) const { return edge_ends_.data() + slot; }
  const Triangle* face_corners_from(std::uint32_t slot) const { return face_corners_.data() + slot; }
  /// The corners of the face in face slot `slot` (the BVH's triangle order): vertex ids, and
  /// vertex slots.
  const Triangle& face_corners(std::uint32_t slot) const { return face_corners_[slot]; }
  /// face_corners() of every face slot in order (nullptr when not built: no leaf rule).
  const Triangle* face_corners_in_order() const { return face_corners_.empty() ? nullptr : face_corners_.data(); }
  const Triangle& face_corner_slots(std::uint32_t slot) const { return face_corner_slots_[slot]; }
  /// A leaf's own pairs that are not adjacent, as masks over the leaf (fixed by connectivity):
  /// for the edge in slot `slot`, bit j set when the edge in slot edge_begin(leaf) + j comes
  /// later in the same leaf and shares no end with it; for the vertex in slot `slot`, bit k
  /// set when face k of its leaf (slot leaf_first + k) does not have it as a corner.
  std::uint64_t apart_edges(std::uint32_t slot) const { return apart_edges_[slot]; }
  std::uint32_t apart_faces(std::uint32_t slot) const { return apart_faces_[slot]; }

  /// The ends of leaf `node`'s edges as a filter (a bit per vertex id, hashed to 256): an edge
  /// with neither end in it shares no end with any of the leaf's edges (may_share_end()).
  struct EndFilter {
    std::uint64_t bits[4];
  };
  const EndFilter& end_filter(std::uint32_t node) const { return end_filters_[node]; }
  static bool may_share_end(const EndFilter& f, const Edge& e) {
    const unsigned h0 = end_hash(e[0]), h1 = end_hash(e[1]);
    return ((f.bits[h0 >> 6] >> (h0 & 63)) | (f.bits[h1 >> 6] >> (h1 & 63))) & 1u;
  }

  /// Storage in leaf order: vertices and edges by owner (isolated vertices last), faces in the
  /// BVH's triangle order.
  const VolumeLayout& layout() const { return layout_; }

 private:
  std::vector<std::uint32_t> vertex_begin_, vertices_;  ///< CSR over BVH nodes
  std::vector<std::uint32_t> edge_begin_, edges_;
  std::vector<std::uint32_t> foreign_begin_, foreign_;  ///< CSR over BVH nodes, vertex slots
  // Copies in leaf order of what leaf pairs read, so that they read it together.
  LargeVector<Edge> edge_ends_;                               ///< per edge slot
  LargeVector<Triangle> face_corners_, face_corner_slots_;  ///< per face slot
  LargeVector<std::uint64_t> apart_edges_;                  ///< per edge slot
  LargeVector<std::uint32_t> apart_faces_;                  ///< per vertex slot
  std::vector<EndFilter> end_filters_;                       ///< per node (empty at inner nodes)
  static unsigned end_hash(std::uint32_t v) { return (v * 0x9E3779B1u) >> 24; }
  VolumeLayout layout_;
};

}  // namespace mccd::detail
