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
/// At a leaf pair (A, B) that meets in some quarters of the step (the BVTT's test of their
/// quarter volumes): each feature A owns against B's quarter volumes in those quarters, and
/// likewise B's against A's; then each surviving vertex against the other leaf's faces and each
/// surviving edge against the other leaf's surviving edges, through the common feature test
/// (core/feature_tests.h) restricted to the quarters both survived in. The features' volumes are
/// stored in leaf order (layout()), so a leaf pair reads a few contiguous runs.
#include <bit>
#include <cstdint>
#include <vector>

#include <mccd/core/bvh.h>
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
  LeafOwnership(const BvhTopology& bvh, const MeshTopology& topo);

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
  /// The vertex ids of the edge in `slot`.
  const Edge& edge_ends(std::uint32_t slot) const { return edge_ends_[slot]; }
  /// The corners of the face in face slot `slot` (the BVH's triangle order): vertex ids, and
  /// vertex slots.
  const Triangle& face_corners(std::uint32_t slot) const { return face_corners_[slot]; }
  const Triangle& face_corner_slots(std::uint32_t slot) const { return face_corner_slots_[slot]; }
  /// A leaf's own pairs that are not adjacent, as masks over the leaf (fixed by connectivity):
  /// for the edge in slot `slot`, bit j set when the edge in slot edge_begin(leaf) + j comes
  /// later in the same leaf and shares no end with it; for the vertex in slot `slot`, bit k
  /// set when face k of its leaf (slot leaf_first + k) does not have it as a corner.
  std::uint64_t apart_edges(std::uint32_t slot) const { return apart_edges_[slot]; }
  std::uint32_t apart_faces(std::uint32_t slot) const { return apart_faces_[slot]; }

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
  VolumeLayout layout_;
};

/// The feature pairs of leaf pairs and of single leaves under the leaf rule.
template <BoundingVolume BV, class NarrowPhase>
class OwnedPairs {
 public:
  using Quarters = QuarterVolume<BV>;
  /// A leaf owns at most 3 vertices and 3 edges per triangle.
  static constexpr unsigned kMaxOwned = 3 * BvhTopology::kMaxLeaf;
  static_assert(kMaxOwned <= 64, "a leaf's owned features as the bits of one 64-bit mask");
  static_assert(BvhTopology::kMaxLeaf <= 32, "a leaf's faces as the bits of one 32-bit mask");

  /// `nodes`: the quarter volumes of the BVH nodes; `unchanged`: leaves that repeat the
  /// previous step (nullptr: none).
  OwnedPairs(const BvhTopology& bvh, const LeafOwnership& owners, const LargeVector<Quarters>& nodes,
             const FeatureTests<BV, NarrowPhase>& tests, const UnchangedLeaves* unchanged = nullptr)
      : bvh_(bvh), owners_(owners), nodes_(nodes), tests_(tests), unchanged_(unchanged) {}

  /// Two different BVH leaves whose quarter volumes overlap in the quarters `within`.
  void process(std::uint32_t a, std::uint32_t b, unsigned within, WorkerOutput& out) const {
    if (tests_.query().stopped() || tests_.too_late(within)) return;
    if (unchanged_ && unchanged_->skip(a, b)) {
      ++out.stats.repeated_leaf_pairs;
      return;
    }
    const std::size_t found = out.contacts.size();
    find(a, b, within, out);
    if (unchanged_ && out.contacts.size() != found) unchanged_->touched(a, b);
  }

  /// The pairs inside one leaf: its owned vertices against its faces, its owned edges against
  /// each other.
  void process_self(std::uint32_t leaf, WorkerOutput& out) const {
    if (tests_.query().stopped()) return;
    if (unchanged_ && unchanged_->skip(leaf, leaf)) {
      ++out.stats.repeated_leaf_pairs;
      return;
    }
    const std::size_t found = out.contacts.size();
    find_self(leaf, out);
    if (unchanged_ && out.contacts.size() != found) unchanged_->touched(leaf, leaf);
  }

 private:
  /// process() past its skips.
  void find(std::uint32_t a, std::uint32_t b, unsigned within, WorkerOutput& out) const {
    ++out.stats.leaf_pairs;
    const Quarters& qa = nodes_[a];
    const Quarters& qb = nodes_[b];
    vertices_against(a, b, qb, within, out);
    vertices_against(b, a, qa, within, out);
    // Edges of each side that may meet the other leaf, with the quarters where they may.
    Surviving ea, eb;
    surviving_edges(a, qb, within, ea);
    if (!ea.n) return;
    surviving_edges(b, qa, within, eb);
    const SweptVolumes<BV>& swept = tests_.swept();
    // Each edge of A against every edge of B without a branch per pair (they mispredict
    // often): the quarters where the two may meet, as bits; then the pairs that may meet.
    // Pairs that share an end always meet in the box slabs (both volumes hold the end's), so
    // they are told apart only among those that pass, and not counted as tests.
    unsigned pieces[kMaxOwned];
    std::uint64_t tested = 0;
    for (unsigned i = 0; i < ea.n; ++i) {
      const Edge& x = ea.ends[i];
      const Quarters& qx = swept.edge_quarters_at(ea.slot[i]);
      const unsigned mi = ea.mask[i];
      std::uint64_t meet = 0;
      for (unsigned j = 0; j < eb.n; ++j) {
        const unsigned m = mi & eb.mask[j];
        tested += m != 0;
        pieces[j] = qx.box_mask(swept.edge_quarters_at(eb.slot[j]), m);
        meet |= std::uint64_t(pieces[j] != 0) << j;
      }
      for (; meet; meet &= meet - 1) {
        const unsigned j = static_cast<unsigned>(std::countr_zero(meet));
        if (shares_end(x, eb.ends[j])) {
          --tested;
          continue;
        }
        const unsigned m = qx.rest_mask(swept.edge_quarters_at(eb.slot[j]), pieces[j]);
        if (m) tests_.test_ee_pieces(ea.id[i], x, eb.id[j], eb.ends[j], m, out);
      }
    }
    out.stats.feature_box_tests += tested;
  }

  /// process_self() past its skips. Only the pairs that are not adjacent (fixed per leaf:
  /// LeafOwnership's apart masks) are tested.
  void find_self(std::uint32_t leaf, WorkerOutput& out) const {
    vertices_against<true>(leaf, leaf, nodes_[leaf], 0xF, out);
    const SweptVolumes<BV>& swept = tests_.swept();
    const std::uint32_t end = owners_.edge_begin(leaf + 1);
    const std::uint32_t begin = owners_.edge_begin(leaf);
    unsigned box[kMaxOwned];
    std::uint64_t tested = 0;
    for (std::uint32_t sa = begin; sa != end; ++sa) {
      // As in process(): the box slabs of every pair, then the rest of those that pass.
      const Quarters& qx = swept.edge_quarters_at(sa);
      const std::uint64_t apart = owners_.apart_edges(sa);
      tested += static_cast<unsigned>(std::popcount(apart));
      std::uint64_t meet = 0;
      for (std::uint64_t r = apart; r; r &= r - 1) {
        const unsigned j = static_cast<unsigned>(std::countr_zero(r));
        box[j] = qx.box_mask(swept.edge_quarters_at(begin + j), 0xFu);
        meet |= std::uint64_t(box[j] != 0) << j;
      }
      for (; meet; meet &= meet - 1) {
        const unsigned j = static_cast<unsigned>(std::countr_zero(meet));
        const unsigned m = qx.rest_mask(swept.edge_quarters_at(begin + j), box[j]);
        if (m)
          tests_.test_ee_pieces(owners_.edge(sa), owners_.edge_ends(sa), owners_.edge(begin + j),
                                owners_.edge_ends(begin + j), m, out);
      }
    }
    out.stats.feature_box_tests += tested;
  }

  /// The vertices leaf `p` owns against the faces of leaf `q` (quarters `qq`); `Self` (p == q):
  /// only the faces that do not have the vertex as a corner.
  template <bool Self = false>
  void vertices_against(std::uint32_t p, std::uint32_t q, const Quarters& qq, unsigned within,
                        WorkerOutput& out) const {
    const SweptVolumes<BV>& swept = tests_.swept();
    const std::uint32_t* faces = bvh_.leaf_triangles(q);
    const std::uint32_t nf = bvh_.leaf_count(q), face_slot = bvh_.leaf_first(q);
    Quarters face_quarters[BvhTopology::kMaxLeaf];
    unsigned merged = 0;  // bit k: face k's quarters merged
    const std::uint32_t begin = owners_.vertex_begin(p);
    unsigned box[kMaxOwned];
    for (std::uint64_t pass = box_pass(begin, owners_.vertex_begin(p + 1), qq, within, box, false); pass;
         pass &= pass - 1) {
      const unsigned j = static_cast<unsigned>(std::countr_zero(pass));
      const std::uint32_t s = begin + j;
      const unsigned m = swept.vertex_quarters_at(s).rest_mask(qq, box[j]);
      if (!m) continue;
      const std::uint32_t v = owners_.vertex(s);
      // The faces whose whole-step volumes meet the vertex's, as bits (no branch per face).
      // (a face with v as a corner always meets v's volume: told apart among those that do,
      // and not counted as a test)
      const BV& vertex_volume = swept.vertex_at(s);
      unsigned meet = 0;
      if constexpr (Self) {
        const unsigned apart = owners_.apart_faces(s);
        for (unsigned r = apart; r; r &= r - 1) {
          const unsigned k = static_cast<unsigned>(std::countr_zero(r));
          meet |= unsigned(vertex_volume.overlaps(swept.face_at(face_slot + k))) << k;
        }
        out.stats.feature_box_tests += static_cast<unsigned>(std::popcount(apart));
      } else {
        for (std::uint32_t k = 0; k < nf; ++k)
          meet |= unsigned(vertex_volume.overlaps(swept.face_at(face_slot + k))) << k;
        out.stats.feature_box_tests += nf;
      }
      for (; meet; meet &= meet - 1) {
        const unsigned k = static_cast<unsigned>(std::countr_zero(meet));
        const Triangle& t = owners_.face_corners(face_slot + k);
        if (!Self && has_corner(t, v)) {
          --out.stats.feature_box_tests;
          continue;
        }
        if (!(merged >> k & 1u)) {
          const Triangle& c = owners_.face_corner_slots(face_slot + k);
          face_quarters[k] = Quarters::merged(swept.vertex_quarters_at(c[0]), swept.vertex_quarters_at(c[1]));
          face_quarters[k].merge(swept.vertex_quarters_at(c[2]));
          merged |= 1u << k;
        }
        tests_.test_vf_quarters(v, swept.vertex_quarters_at(s), t, faces[k], face_quarters[k], out, m);
      }
    }
  }

  /// For the vertex (edges: `edges`) slots [begin, end) of one leaf against quarters `qq`: the
  /// box_mask of each in `box` (by slot - begin), and a bit per slot where it is non-zero.
  std::uint64_t box_pass(std::uint32_t begin, std::uint32_t end, const Quarters& qq, unsigned within, unsigned* box,
                         bool edges) const {
    const SweptVolumes<BV>& swept = tests_.swept();
    std::uint64_t pass = 0;
    for (std::uint32_t s = begin; s != end; ++s) {
      const Quarters& q = edges ? swept.edge_quarters_at(s) : swept.vertex_quarters_at(s);
      box[s - begin] = q.box_mask(qq, within);
      pass |= std::uint64_t(box[s - begin] != 0) << (s - begin);
    }
    return pass;
  }

  /// Owned edges that may meet a leaf: ids, slots and the quarters where they may.
  struct Surviving {
    std::uint32_t id[kMaxOwned], slot[kMaxOwned];
    Edge ends[kMaxOwned];
    unsigned mask[kMaxOwned];
    unsigned n = 0;
  };
  /// The edges leaf `p` owns that may meet quarters `qq` within `within`.
  void surviving_edges(std::uint32_t p, const Quarters& qq, unsigned within, Surviving& out) const {
    const SweptVolumes<BV>& swept = tests_.swept();
    // The box slabs of every edge without a branch per edge, then the other slabs of those
    // that pass, kept without a branch.
    const std::uint32_t begin = owners_.edge_begin(p);
    unsigned box[kMaxOwned];
    const std::uint64_t pass = box_pass(begin, owners_.edge_begin(p + 1), qq, within, box, true);
    for (std::uint64_t rest = pass; rest; rest &= rest - 1) {
      const unsigned k = static_cast<unsigned>(std::countr_zero(rest));
      const std::uint32_t s = begin + k;
      const unsigned m = swept.edge_quarters_at(s).rest_mask(qq, box[k]);
      out.id[out.n] = owners_.edge(s);
      out.slot[out.n] = s;
      out.ends[out.n] = owners_.edge_ends(s);
      out.mask[out.n] = m;
      out.n += m != 0;
    }
  }

  const BvhTopology& bvh_;
  const LeafOwnership& owners_;
  const LargeVector<Quarters>& nodes_;
  const FeatureTests<BV, NarrowPhase>& tests_;
  const UnchangedLeaves* unchanged_;
};

}  // namespace mccd::detail
