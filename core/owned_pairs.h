#pragma once
/// @file Internal: the feature pairs of leaf pairs and of single leaves under the leaf rule
/// (core/leaf_owners.h).
///
/// At a leaf pair (A, B) that the BVTT found overlapping: each vertex A owns against B's faces
/// and each of B's against A's, each edge A owns against B's; inside a single leaf, its vertices
/// against its faces and its edges against each other, the pairs that are not adjacent only
/// (LeafOwnership's apart masks). A pair of features sharing a vertex is never tested.
///
/// First on coarse whole-step volumes (16-bit k-DOPs in lanes, core/leaf_lanes.h): the
/// features of each leaf against the other leaf's own, then each surviving feature of one leaf
/// against all of the other's at once (geometry/lane_masks.h). Coarse volumes never separate
/// what the float ones do not, so they only skip pairs. Each pair they do not separate (a
/// feature-pair test in the statistics) is tested on the features' float quarter volumes, and
/// the quarters in which those overlap go with the pair to the narrow phase, queued
/// (FeatureTests::queue_vf, queue_ee; run by finish()). That is the same for every way of
/// reaching the pair (brute force, the canonical rule): a pair's own quarter volumes lie inside
/// those of its leaves, so testing them first changes nothing.
#include <bit>
#include <cstdint>

#include <mccd/core/bvh.h>
#include <mccd/core/feature_tests.h>
#include <mccd/core/leaf_lanes.h>
#include <mccd/core/leaf_owners.h>
#include <mccd/core/unchanged_leaves.h>
#include <mccd/geometry/lane_masks.h>

namespace mccd::detail {

template <BoundingVolume BV, class NarrowPhase>
class OwnedPairs {
 public:
  using Quarters = QuarterVolume<BV>;
  using Lanes = LeafLanes<BV>;
  using Tests = FeatureTests<BV, NarrowPhase>;
  /// A leaf owns at most 3 vertices and 3 edges per triangle.
  static constexpr unsigned kMaxOwned = 3 * BvhTopology::kMaxLeaf;
  static_assert(kMaxOwned <= kMaxLanes, "a leaf's owned features as the bits of one 64-bit mask");
  static_assert(BvhTopology::kMaxLeaf <= 32, "a leaf's faces as the bits of one 32-bit mask");

  /// `nodes`: the quarter volumes of the BVH nodes; `lanes`: the leaves' lane blocks (filled
  /// when first used in a step); `unchanged`: leaves that repeat the previous step (nullptr:
  /// none).
  OwnedPairs(const BvhTopology& bvh, const LeafOwnership& owners, const LargeVector<Quarters>& nodes,
             const Lanes& lanes, const FeatureTests<BV, NarrowPhase>& tests,
             const UnchangedLeaves* unchanged = nullptr)
      : bvh_(bvh), owners_(owners), nodes_(nodes), lanes_(lanes), tests_(tests), unchanged_(unchanged) {}

  /// Two different BVH leaves whose quarter volumes overlap in the quarters `within`; their
  /// pairs past the volume tests are queued in `out` (finish() runs what is left).
  void process(std::uint32_t a, std::uint32_t b, unsigned within, WorkerOutput& out) const {
    if (tests_.query().stopped() || tests_.too_late(within)) return;
    if (unchanged_ && unchanged_->skip(a, b)) {
      ++out.stats.repeated_leaf_pairs;
      return;
    }
    find(a, b, out);
    if (out.queued.size() >= Tests::kQueue) finish(out);
  }

  /// Reads what a leaf pair (a, b) reads first, to have it in the cache when it comes: plain
  /// loads, independent of each other, so that their cache misses overlap (a leaf pair's own
  /// loads depend on each other and wait one after another; software prefetches did not help).
  /// Only what no thread writes during the search: what filling the leaves' lanes reads
  /// (LeafLanes::ensure), not the lanes.
  std::uint32_t touch(std::uint32_t a, std::uint32_t b) const {
    std::uint32_t sum = 0;
    auto lines = [&](const void* from, const void* to) {
      for (const char* p = static_cast<const char*>(from); p < static_cast<const char*>(to); p += 64)
        sum += static_cast<unsigned char>(*p);
    };
    for (std::uint32_t x : {a, b}) {
      const std::uint32_t vb = owners_.vertex_begin(x), ve = owners_.vertex_begin(x + 1);
      const std::uint32_t eb = owners_.edge_begin(x), ee = owners_.edge_begin(x + 1);
      const std::uint32_t fb = bvh_.leaf_first(x), fe = fb + bvh_.leaf_count(x);
      lines(&lanes_.vertex(vb), &lanes_.vertex(ve));
      lines(&tests_.swept().edge_end_slots_at(eb), &tests_.swept().edge_end_slots_at(ee));
      lines(&owners_.face_corner_slots(fb), &owners_.face_corner_slots(fe));
      lines(&owners_.edge_ends(eb), &owners_.edge_ends(ee));
      lines(&owners_.face_corners(fb), &owners_.face_corners(fe));
    }
    return sum;
  }

  /// The pairs inside one leaf: its owned vertices against its faces, its owned edges against
  /// each other.
  void process_self(std::uint32_t leaf, WorkerOutput& out) const {
    if (tests_.query().stopped()) return;
    if (unchanged_ && unchanged_->skip(leaf, leaf)) {
      ++out.stats.repeated_leaf_pairs;
      return;
    }
    find_self(leaf, out);
    if (out.queued.size() >= Tests::kQueue) finish(out);
  }

  /// The narrow phase of the feature pairs queued in `out` (FeatureTests::run_queued); the
  /// leaves of those that find a contact are marked for the next step (UnchangedLeaves).
  void finish(WorkerOutput& out) const {
    tests_.run_queued(out, [this](std::uint32_t a, std::uint32_t b) {
      if (unchanged_) unchanged_->touched(a, b);
    });
  }

 private:
  using Block = typename Lanes::Block;
  static constexpr unsigned kSlabs = BV::kSlabs;

  /// Leaf `node`'s lanes, filled for the step.
  void ensure(std::uint32_t node) const { lanes_.ensure(node, bvh_, owners_, nodes_[node]); }

  /// The lanes of `block` whose coarse volumes meet leaf `other`'s.
  std::uint64_t meeting_leaf(const Block& block, std::uint32_t other) const {
    std::uint64_t m = 0;
    if (block.n) lane_kernels().dops(block.rows, block.stride, block.n, kSlabs, &lanes_.leaf(other), 1, &m);
    return m;
  }

  /// The coarse volume of the edge in `slot` (the merge of its ends').
  CoarseDop edge_coarse(std::uint32_t slot) const {
    const Edge& e = tests_.swept().edge_end_slots_at(slot);
    return Lanes::merged(lanes_.vertex(e[0]), lanes_.vertex(e[1]));
  }

  /// The lanes set in `chosen`, in order, into `lanes`; their number.
  static unsigned lane_list(std::uint64_t chosen, std::uint8_t* lanes) {
    unsigned n = 0;
    for (; chosen; chosen &= chosen - 1) lanes[n++] = static_cast<std::uint8_t>(std::countr_zero(chosen));
    return n;
  }

  /// process() past its skips.
  void find(std::uint32_t a, std::uint32_t b, WorkerOutput& out) const {
    ++out.stats.leaf_pairs;
    ensure(a);
    ensure(b);
    vertices_against(a, b, out);
    vertices_against(b, a, out);
    // Edges of each side whose coarse volumes meet the other leaf's, then each such edge of A
    // against B's in lanes, then the float quarter volumes of the pairs that meet there.
    // Pairs that share an end always meet (both volumes hold the end's): they are told apart
    // among those, and not counted as tests. B's edges' quarter volumes are merged from their
    // ends' when first needed.
    const Block ea = lanes_.edges(a, owners_), eb = lanes_.edges(b, owners_);
    const std::uint64_t alive_a = meeting_leaf(ea, b);
    if (!alive_a) return;
    const std::uint64_t alive_b = meeting_leaf(eb, a);
    if (!alive_b) return;
    const std::uint32_t fa = owners_.edge_begin(a), fb = owners_.edge_begin(b);
    std::uint8_t lanes[kMaxOwned];
    const unsigned n = lane_list(alive_a, lanes);
    CoarseDop others[kMaxOwned];
    for (unsigned i = 0; i < n; ++i) others[i] = edge_coarse(fa + lanes[i]);
    std::uint64_t met[kMaxOwned];
    lane_kernels().dops(eb.rows, eb.stride, eb.n, kSlabs, others, n, met);
    const SweptVolumes<BV>& swept = tests_.swept();
    Quarters qb[kMaxOwned];
    std::uint64_t merged = 0;
    std::uint64_t tested = 0;
    for (unsigned i = 0; i < n; ++i) {
      const std::uint32_t sa = fa + lanes[i];
      const Edge& x = owners_.edge_ends(sa);
      std::uint64_t meet = met[i] & alive_b;
      // (pairs sharing an end: not tested, not counted)
      for (std::uint64_t r = meet; r; r &= r - 1) {
        const unsigned j = static_cast<unsigned>(std::countr_zero(r));
        if (shares_end(x, owners_.edge_ends(fb + j))) meet &= ~(std::uint64_t(1) << j);
      }
      if (!meet) continue;
      Quarters qx;
      swept.edge_quarters_into(sa, qx);
      for (; meet; meet &= meet - 1) {
        const unsigned j = static_cast<unsigned>(std::countr_zero(meet));
        const std::uint32_t sb = fb + j;
        if (!(merged >> j & 1u)) {
          swept.edge_quarters_into(sb, qb[j]);
          merged |= std::uint64_t(1) << j;
        }
        ++tested;
        if (const unsigned m = qx.overlap_mask(qb[j]))
          tests_.queue_ee(owners_.edge(sa), x, owners_.edge(sb), owners_.edge_ends(sb), m, a, b, out);
      }
    }
    out.stats.feature_box_tests += tested;
  }

  /// process_self() past its skips. Only the pairs that are not adjacent (fixed per leaf:
  /// LeafOwnership's apart masks) are tested.
  void find_self(std::uint32_t leaf, WorkerOutput& out) const {
    ensure(leaf);
    vertices_against<true>(leaf, leaf, out);
    // Each edge against the later ones it shares no end with: as in find().
    const Block block = lanes_.edges(leaf, owners_);
    const std::uint32_t begin = owners_.edge_begin(leaf);
    std::uint64_t with_later = 0;
    for (unsigned i = 0; i < block.n; ++i) with_later |= std::uint64_t(owners_.apart_edges(begin + i) != 0) << i;
    std::uint8_t lanes[kMaxOwned];
    const unsigned n = lane_list(with_later, lanes);
    CoarseDop others[kMaxOwned];
    for (unsigned i = 0; i < n; ++i) others[i] = edge_coarse(begin + lanes[i]);
    std::uint64_t met[kMaxOwned];
    lane_kernels().dops(block.rows, block.stride, block.n, kSlabs, others, n, met);
    const SweptVolumes<BV>& swept = tests_.swept();
    Quarters q[kMaxOwned];  // the leaf's edges' quarters, merged when first needed
    std::uint64_t merged = 0;
    auto quarters = [&](unsigned j) -> const Quarters& {
      if (!(merged >> j & 1u)) {
        swept.edge_quarters_into(begin + j, q[j]);
        merged |= std::uint64_t(1) << j;
      }
      return q[j];
    };
    std::uint64_t tested = 0;
    for (unsigned i = 0; i < n; ++i) {
      const std::uint32_t sa = begin + lanes[i];
      std::uint64_t meet = met[i] & owners_.apart_edges(sa);
      if (!meet) continue;
      const Quarters& qx = quarters(lanes[i]);
      for (; meet; meet &= meet - 1) {
        const unsigned j = static_cast<unsigned>(std::countr_zero(meet));
        const std::uint32_t sb = begin + j;
        ++tested;
        if (const unsigned m = qx.overlap_mask(quarters(j)))
          tests_.queue_ee(owners_.edge(sa), owners_.edge_ends(sa), owners_.edge(sb), owners_.edge_ends(sb), m, leaf,
                          leaf, out);
      }
    }
    out.stats.feature_box_tests += tested;
  }

  /// The vertices leaf `p` owns against the faces of leaf `q`; `Self` (p == q): only the faces
  /// that do not have the vertex as a corner (a face with the vertex as a corner always meets
  /// it: told apart among those that do, and not counted as a test).
  template <bool Self = false>
  void vertices_against(std::uint32_t p, std::uint32_t q, WorkerOutput& out) const {
    const Block vp = lanes_.vertices(p, owners_), fq = lanes_.faces(q, bvh_);
    const std::uint64_t alive =
        Self ? (vp.n >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << vp.n) - 1) : meeting_leaf(vp, q);
    if (!alive || !fq.n) return;
    const std::uint32_t begin = owners_.vertex_begin(p);
    std::uint8_t lanes[kMaxOwned];
    const unsigned n = lane_list(alive, lanes);
    CoarseDop others[kMaxOwned];
    for (unsigned i = 0; i < n; ++i) others[i] = lanes_.vertex(begin + lanes[i]);
    std::uint64_t met[kMaxOwned];
    lane_kernels().dops(fq.rows, fq.stride, fq.n, kSlabs, others, n, met);
    const SweptVolumes<BV>& swept = tests_.swept();
    const std::uint32_t* faces = bvh_.leaf_triangles(q);
    const std::uint32_t face_slot = bvh_.leaf_first(q);
    Quarters face_quarters[BvhTopology::kMaxLeaf];
    unsigned merged = 0;  // bit k: face k's quarters merged
    std::uint64_t tested = 0;
    for (unsigned i = 0; i < n; ++i) {
      const std::uint32_t s = begin + lanes[i];
      const std::uint32_t v = owners_.vertex(s);
      std::uint64_t meet = met[i];
      if constexpr (Self) meet &= owners_.apart_faces(s);
      for (; meet; meet &= meet - 1) {
        const unsigned k = static_cast<unsigned>(std::countr_zero(meet));
        const Triangle& t = owners_.face_corners(face_slot + k);
        if (!Self && has_corner(t, v)) continue;
        ++tested;
        if (!(merged >> k & 1u)) {
          const Triangle& c = owners_.face_corner_slots(face_slot + k);
          face_quarters[k].merge_of(swept.vertex_quarters_at(c[0]), swept.vertex_quarters_at(c[1]));
          face_quarters[k].merge(swept.vertex_quarters_at(c[2]));
          merged |= 1u << k;
        }
        tests_.queue_vf(v, swept.vertex_quarters_at(s), t, faces[k], face_quarters[k], p, q, out);
      }
    }
    out.stats.feature_box_tests += tested;
  }

  const BvhTopology& bvh_;
  const LeafOwnership& owners_;
  const LargeVector<Quarters>& nodes_;
  const Lanes& lanes_;
  const FeatureTests<BV, NarrowPhase>& tests_;
  const UnchangedLeaves* unchanged_;
};

}  // namespace mccd::detail
