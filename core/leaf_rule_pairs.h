#pragma once
/// @file Internal: the feature pairs of leaf pairs and of single leaves under the leaf rule
/// (core/leaf_rule_owners.h).
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
/// (FeatureTests::vf_entry, ee_entry; run by finish()). That is the same for every way of
/// reaching the pair (brute force, the canonical rule): a pair's own quarter volumes lie inside
/// those of its leaves, so testing them first changes nothing.
///
/// At leaves that move little against their edges' lengths (LeafLanes::still;
/// SceneOptions::volume_order) nearly every such pair's volumes meet, and most pairs are then
/// removed by the coplanarity filter: there a pair is queued with its leaf pair's quarters and
/// its own volumes are tested after the filter, only if the filter keeps it
/// (FeatureTests::kVolumesPending; the same contacts and elementary tests).
#include <bit>
#include <cstdint>

#include <mccd/core/bvh.h>
#include <mccd/core/feature_tests.h>
#include <mccd/core/leaf_lanes.h>
#include <mccd/core/leaf_rule_owners.h>
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
    ensure(a);
    ensure(b);
    // the AVX-512 copy where the quarter volumes are tested up front (not for leaves that
    // barely move, whose loops only queue their pairs)
    const bool defer = deferring_ && lanes_.still(a) && lanes_.still(b);
    if (wide() && !defer)
      find_wide(a, b, within, out);
    else
      find<false>(a, b, within, defer, out);
    if (out.queued.size() >= Tests::kQueue) finish(out);
  }

  /// The pairs inside one leaf: its owned vertices against its faces, its owned edges against
  /// each other.
  void process_self(std::uint32_t leaf, WorkerOutput& out) const {
    if (tests_.query().stopped()) return;
    if (unchanged_ && unchanged_->skip(leaf, leaf)) {
      ++out.stats.repeated_leaf_pairs;
      return;
    }
    ensure(leaf);
    const bool defer = deferring_ && lanes_.still(leaf);
    if (wide() && !defer)  // as in process()
      find_self_wide(leaf, out);
    else
      find_self<false>(leaf, defer, out);
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
  static constexpr unsigned kSlabs = BV::kSlabs;
#if defined(MCCD_WIDE_QUARTERS)
  static constexpr bool kWideable = kSlabs == 9;
#else
  static constexpr bool kWideable = false;
#endif

  /// Whether the leaf pairs' loops run their AVX-512 copies (find_wide(), find_self_wide()):
  /// the 18-DOP, on a processor with AVX-512 at the level in use (MCCD_SIMD can ask for less).
  static bool wide() { return kWideable && lane_kernels().level == SimdLevel::Avx512; }
#if defined(MCCD_WIDE_QUARTERS)
  /// find() and find_self() compiled for AVX-512, every call inlined (the quarter volumes' tests
  /// and merges in its registers: wide_overlap_mask() and the merges in quarter_volumes.h).
  MCCD_WIDE_TARGET __attribute__((flatten)) void find_wide(std::uint32_t a, std::uint32_t b, unsigned within,
                                                           WorkerOutput& out) const {
    if constexpr (kWideable) find<true>(a, b, within, false, out);
  }
  MCCD_WIDE_TARGET __attribute__((flatten)) void find_self_wide(std::uint32_t leaf, WorkerOutput& out) const {
    if constexpr (kWideable) find_self<true>(leaf, false, out);
  }
#else
  void find_wide(std::uint32_t, std::uint32_t, unsigned, WorkerOutput&) const {}
  void find_self_wide(std::uint32_t, WorkerOutput&) const {}
#endif
  /// The quarter volumes' operations in SSE2 or (Wide) in AVX-512: out.merge_of(a, b),
  /// out.merge(o), and a.overlap_mask(b) as overlap(hold(a, room), b).
  template <bool Wide>
  static void merged_into(Quarters& out, const Quarters& a, const Quarters& b) {
#if defined(MCCD_WIDE_QUARTERS)
    if constexpr (Wide) return wide_merge_of(out, a, b);
#endif
    out.merge_of(a, b);
  }
  template <bool Wide>
  static void merge_into(Quarters& out, const Quarters& o) {
#if defined(MCCD_WIDE_QUARTERS)
    if constexpr (Wide) return wide_merge(out, o);
#endif
    out.merge(o);
  }
  /// What overlap() takes for `a`: a itself, or with Wide its bounds swapped (wide_swapped())
  /// into `room`.
  template <bool Wide>
  static const Quarters& hold(const Quarters& a, Quarters& room) {
#if defined(MCCD_WIDE_QUARTERS)
    if constexpr (Wide) {
      wide_swapped(a, room);
      return room;
    }
#endif
    return a;
  }
  template <bool Wide>
  static unsigned overlap(const Quarters& held, const Quarters& b) {
#if defined(MCCD_WIDE_QUARTERS)
    if constexpr (Wide) return wide_overlap_mask(held, b);
#endif
    return held.overlap_mask(b);
  }
  /// swept.edge_quarters_into(slot, q).
  template <bool Wide>
  static void edge_quarters(const SweptVolumes<BV>& swept, std::uint32_t slot, Quarters& q) {
    const Edge& c = swept.edge_end_slots_at(slot);
    merged_into<Wide>(q, swept.vertex_quarters_at(c[0]), swept.vertex_quarters_at(c[1]));
  }

  /// Leaf `node`'s lanes, filled for the step.
  void ensure(std::uint32_t node) const {
    lanes_.ensure(node, bvh_, owners_, nodes_[node], unchanged_ && unchanged_->repeats(node));
  }

  /// process() past its skips, the leaves' lanes filled; `defer`: both leaves barely move.
  template <bool Wide>
  void find(std::uint32_t a, std::uint32_t b, unsigned within, bool defer, WorkerOutput& out) const {
    ++out.stats.leaf_pairs;
    // The coarse tests of the two leaves at once (LaneKernels::pair_masks), then the float
    // quarter volumes of the pairs they do not separate.
    PairMasks m;
    lane_kernels().pair_masks(kSlabs, lanes_.blocks(a, bvh_, owners_), lanes_.blocks(b, bvh_, owners_), m);
    vertices_against<false, Wide>(a, b, m.alive_va, m.vertex_faces_ab, out, defer, within);
    vertices_against<false, Wide>(b, a, m.alive_vb, m.vertex_faces_ba, out, defer, within);
    if (!m.alive_ea || !m.alive_eb) return;
    // Pairs of edges that share an end always meet (both volumes hold the end's): they are
    // told apart among those, and not counted as tests.
    const SweptVolumes<BV>& swept = tests_.swept();
    const std::uint32_t fa = owners_.edge_begin(a), fb = owners_.edge_begin(b);
    Quarters qb[kMaxOwned];
    if (!defer) {  // B's edges' quarter volumes, merged from their ends' where any of A's meets them
      std::uint64_t need = 0;
      for (std::uint64_t left = m.alive_ea; left; left &= left - 1) need |= m.edges[std::countr_zero(left)];
      for (; need; need &= need - 1) {
        const unsigned j = static_cast<unsigned>(std::countr_zero(need));
        edge_quarters<Wide>(swept, fb + j, qb[j]);
      }
    }
    const LeafOwnership::EndFilter& ends_b = owners_.end_filter(b);  // most edges share no end with b's
    // B's edges (ids and ends) through pointers held here: the queue's byte fields may alias
    // anything, so members read through the owners would be read again after every write
    const std::uint32_t* ids_b = owners_.edges_from(fb);
    const Edge* ends_at_b = owners_.edge_ends_from(fb);
    std::uint64_t tested = 0;
    for (std::uint64_t left = m.alive_ea; left; left &= left - 1) {
      const std::uint32_t sa = fa + static_cast<unsigned>(std::countr_zero(left));
      const Edge x = owners_.edge_ends(sa);
      std::uint64_t meet = m.edges[sa - fa];
      const std::uint32_t ea = owners_.edge(sa);
      if (!meet) continue;
      // every pair written at the queue's end (room for a mask's 64 bits: a population count is
      // a library call in a portable build), kept by moving the end
      QueuedPair* end = out.queued.room(64);
      if (defer) {  // kept unless the edges share an end (no branch on that), volumes tested later
        const unsigned pending = within | Tests::kVolumesPending;
        for (; meet; meet &= meet - 1) {
          const unsigned j = static_cast<unsigned>(std::countr_zero(meet));
          const bool keep = !shares_end(x, ends_at_b[j]);
          tested += keep;
          *end = Tests::ee_entry(ea, x, ids_b[j], ends_at_b[j], pending, a, b);
          end += keep;
        }
        out.queued.set_end(end);
        continue;
      }
      if (LeafOwnership::may_share_end(ends_b, x))
        for (std::uint64_t r = meet; r; r &= r - 1) {
          const unsigned j = static_cast<unsigned>(std::countr_zero(r));
          if (shares_end(x, ends_at_b[j])) meet &= ~(std::uint64_t(1) << j);
        }
      if (!meet) continue;
      Quarters qx, room;
      edge_quarters<Wide>(swept, sa, qx);
      const Quarters& held = hold<Wide>(qx, room);
      for (; meet; meet &= meet - 1) {  // kept where the quarters meet: no branch on that
        const unsigned j = static_cast<unsigned>(std::countr_zero(meet));
        ++tested;
        const unsigned mq = overlap<Wide>(held, qb[j]);
        *end = Tests::ee_entry(ea, x, ids_b[j], ends_at_b[j], mq, a, b);
        end += mq != 0;
      }
      out.queued.set_end(end);
    }
    out.stats.feature_box_tests += tested;
  }

  /// process_self() past its skips, the leaf's lanes filled. Only the pairs that are not
  /// adjacent (fixed per leaf: LeafOwnership's apart masks) are tested; `defer`: the leaf
  /// barely moves.
  template <bool Wide>
  void find_self(std::uint32_t leaf, bool defer, WorkerOutput& out) const {
    const std::uint32_t begin = owners_.edge_begin(leaf), ne = owners_.edge_begin(leaf + 1) - begin;
    // each edge against the later ones it shares no end with
    std::uint64_t with_later = 0;
    for (unsigned i = 0; i < ne; ++i) with_later |= std::uint64_t(owners_.apart_edges(begin + i) != 0) << i;
    SelfMasks m;
    lane_kernels().self_masks(kSlabs, lanes_.blocks(leaf, bvh_, owners_), with_later, m);
    const std::uint32_t nv = owners_.vertex_begin(leaf + 1) - owners_.vertex_begin(leaf);
    const std::uint64_t all = nv >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << nv) - 1;
    vertices_against<true, Wide>(leaf, leaf, all, m.vertex_faces, out, defer, 0xF);
    const SweptVolumes<BV>& swept = tests_.swept();
    Quarters q[kMaxOwned];  // the leaf's edges' quarters, merged where a pair needs them
    if (!defer) {
      std::uint64_t need = 0;
      for (std::uint64_t left = with_later; left; left &= left - 1) {
        const unsigned i = static_cast<unsigned>(std::countr_zero(left));
        const std::uint64_t meet = m.edges[i] & owners_.apart_edges(begin + i);
        need |= meet | (meet ? std::uint64_t(1) << i : 0);
      }
      for (; need; need &= need - 1) {
        const unsigned j = static_cast<unsigned>(std::countr_zero(need));
        edge_quarters<Wide>(swept, begin + j, q[j]);
      }
    }
    const std::uint32_t* ids = owners_.edges_from(begin);  // held here, as in find()
    const Edge* ends = owners_.edge_ends_from(begin);
    std::uint64_t tested = 0;
    for (std::uint64_t left = with_later; left; left &= left - 1) {
      const unsigned i = static_cast<unsigned>(std::countr_zero(left));
      const std::uint32_t sa = begin + i;
      std::uint64_t meet = m.edges[i] & owners_.apart_edges(sa);
      if (!meet) continue;
      const std::uint32_t ea = ids[i];
      QueuedPair* end = out.queued.room(64);  // as in find()
      if (defer) {
        for (; meet; meet &= meet - 1) {
          ++tested;
          const unsigned j = static_cast<unsigned>(std::countr_zero(meet));
          *end++ = Tests::ee_entry(ea, ends[i], ids[j], ends[j], 0xF | Tests::kVolumesPending, leaf, leaf);
        }
        out.queued.set_end(end);
        continue;
      }
      Quarters room;
      const Quarters& held = hold<Wide>(q[i], room);
      for (; meet; meet &= meet - 1) {
        const unsigned j = static_cast<unsigned>(std::countr_zero(meet));
        ++tested;
        const unsigned mq = overlap<Wide>(held, q[j]);
        *end = Tests::ee_entry(ea, ends[i], ids[j], ends[j], mq, leaf, leaf);
        end += mq != 0;
      }
      out.queued.set_end(end);
    }
    out.stats.feature_box_tests += tested;
  }

  /// The vertices `alive` of those leaf `p` owns against the faces of leaf `q` they meet
  /// (met[j] for vertex lane j); `Self` (p == q): only the faces that do not have the vertex as
  /// a corner (a face with the vertex as a corner always meets it: told apart among those that
  /// do, and not counted as a test). `defer`: queued with the quarters `within` (holding those
  /// of their volumes), the volumes tested after the filter.
  template <bool Self, bool Wide>
  void vertices_against(std::uint32_t p, std::uint32_t q, std::uint64_t alive, const std::uint64_t* met,
                        WorkerOutput& out, bool defer, unsigned within) const {
    const SweptVolumes<BV>& swept = tests_.swept();
    const std::uint32_t* faces = bvh_.leaf_triangles(q);
    const std::uint32_t face_slot = bvh_.leaf_first(q), begin = owners_.vertex_begin(p);
    auto meets = [&](unsigned lane) {
      std::uint64_t meet = met[lane];
      if constexpr (Self) meet &= owners_.apart_faces(begin + lane);
      return meet;
    };
    Quarters face_quarters[BvhTopology::kMaxLeaf];
    if (!defer) {  // the faces' quarter volumes, merged from their corners' where a vertex meets them
      std::uint64_t need = 0;
      for (std::uint64_t left = alive; left; left &= left - 1)
        need |= meets(static_cast<unsigned>(std::countr_zero(left)));
      for (; need; need &= need - 1) {
        const unsigned k = static_cast<unsigned>(std::countr_zero(need));
        const Triangle& c = owners_.face_corner_slots(face_slot + k);
        merged_into<Wide>(face_quarters[k], swept.vertex_quarters_at(c[0]), swept.vertex_quarters_at(c[1]));
        merge_into<Wide>(face_quarters[k], swept.vertex_quarters_at(c[2]));
      }
    }
    const Triangle* corners = owners_.face_corners_from(face_slot);  // held here, as in find()
    std::uint64_t tested = 0;
    for (; alive; alive &= alive - 1) {
      const unsigned lane = static_cast<unsigned>(std::countr_zero(alive));
      const std::uint32_t s = begin + lane;
      const std::uint32_t v = owners_.vertex(s);
      std::uint64_t meet = meets(lane);
      if (!meet) continue;
      // every pair written at the queue's end, as in find()
      QueuedPair* end = out.queued.room(64);
      if (defer) {  // kept unless the face has the vertex as a corner: no branch on that
        const unsigned pending = within | Tests::kVolumesPending;
        for (; meet; meet &= meet - 1) {
          const unsigned k = static_cast<unsigned>(std::countr_zero(meet));
          const Triangle& t = corners[k];
          const bool keep = Self || !has_corner(t, v);
          tested += keep;
          *end = Tests::vf_entry(v, t, faces[k], pending, p, q);
          end += keep;
        }
        out.queued.set_end(end);
        continue;
      }
      Quarters room;
      const Quarters& held = hold<Wide>(swept.vertex_quarters_at(s), room);
      for (; meet; meet &= meet - 1) {  // kept where the quarters meet: no branch on that
        const unsigned k = static_cast<unsigned>(std::countr_zero(meet));
        const Triangle& t = corners[k];
        if (!Self && has_corner(t, v)) continue;
        ++tested;
        const unsigned mq = overlap<Wide>(held, face_quarters[k]);
        *end = Tests::vf_entry(v, t, faces[k], mq, p, q);
        end += mq != 0;
      }
      out.queued.set_end(end);
    }
    out.stats.feature_box_tests += tested;
  }

  const BvhTopology& bvh_;
  const LeafOwnership& owners_;
  const LargeVector<Quarters>& nodes_;
  const Lanes& lanes_;
  const FeatureTests<BV, NarrowPhase>& tests_;
  const UnchangedLeaves* unchanged_;
  /// Whether the narrow phase filters queued pairs before it tests them one by one (without
  /// that, testing the volumes later saves nothing).
  bool deferring_ = tests_.prefilters();
};

}  // namespace mccd::detail
