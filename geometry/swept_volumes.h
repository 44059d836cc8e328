#pragma once
/// @file Internal: the swept volumes of one step, per vertex, edge and face, over the whole step
/// and over its quarters, for one bounding-volume type.
///
/// A vertex moves on a segment from x0 to x1. Its quarter volumes bound the straight paths
/// between the computed points a + (k/4)(b - a), k = 0..4, moved out (see update_vertices) so
/// that each contains the exact part of the segment in [q/4, (q+1)/4]; its whole-step volume
/// is the merge of its four quarter volumes (derived where it is read, not stored). An edge's
/// and a face's volumes (whole or per quarter) are the merges of their vertices'. A contact at
/// time t lies in both features' volumes of every quarter holding t, so two features can only
/// meet in the quarters where their quarter volumes overlap.
///
/// Consistency invariant that makes every method return identical contacts: a feature pair
/// reaches the elementary test only when its features' quarter volumes overlap in some
/// quarter (core/feature_tests.h). Every quarter volume lies inside the feature's whole-step
/// volume, hence inside the volume of every triangle around the feature and of every BVH node
/// above it, so whenever that test passes every carrier of the pair and all its ancestors
/// overlap, and every method reaches the pair. Whole-step tests and masks of quarters from
/// larger volumes (`within`) are implied by the quarter test, so they only save work.
///
/// Stored: per vertex its quarters only (288 bytes for the 18-DOP). Its whole-step volume is
/// their merge, exact in float, so it is computed where it is read: storing it added half again
/// to what the update writes every step. An edge's and a face's volumes are merged from their
/// vertices' when needed (stored, an edge's quarters took more memory than all the rest, and
/// the leaf pairs ask for few of them).
/// Storage is in a layout of slots chosen by the caller (VolumeLayout: the BVH's leaf order,
/// so that the features a leaf pair reads lie together in memory); accessors take ids, or
/// slots where the caller already knows them.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <mccd/geometry/kdop.h>
#include <mccd/geometry/lane_masks.h>
#include <mccd/geometry/large_allocator.h>
#include <mccd/geometry/quarter_volumes.h>
#include <mccd/geometry/topology.h>

namespace mccd::detail {

/// Where each vertex, edge and face is stored: slot[id], a permutation of the ids (empty: the
/// identity).
struct VolumeLayout {
  std::vector<std::uint32_t> vertex_slot, edge_slot, face_slot;
};

template <BoundingVolume BV>
class SweptVolumes {
 public:
  using Quarters = QuarterVolume<BV>;

  void resize(const MeshTopology& topo, VolumeLayout layout = {}) {
    resize(topo, std::move(layout), [](std::size_t n, const auto& body) { body(std::size_t(0), n); });
  }
  /// The same, with the inverse maps of the layout filled through `for_chunks(n, body)` (body(begin,
  /// end) over element indices; a parallel loop: megabytes for a large scene).
  template <class ForChunks>
  void resize(const MeshTopology& topo, VolumeLayout layout, const ForChunks& for_chunks) {
    layout_ = std::move(layout);
    auto identity = [](std::vector<std::uint32_t>& slot, std::size_t n) {
      if (!slot.empty()) return;
      slot.resize(n);
      for (std::size_t i = 0; i < n; ++i) slot[i] = static_cast<std::uint32_t>(i);
    };
    identity(layout_.vertex_slot, topo.num_vertices());
    identity(layout_.edge_slot, topo.num_edges());
    identity(layout_.face_slot, topo.num_faces());
    // The inverse maps of the slot-order update: each slot's vertex, each edge slot's and face
    // slot's vertices as slots. The layout is a permutation: every entry is written once.
    vertex_of_slot_.resize(topo.num_vertices());
    edge_end_slots_.resize(topo.num_edges());
    face_corner_slots_.resize(topo.num_faces());
    const std::vector<std::uint32_t>& vs = layout_.vertex_slot;
    for_chunks(topo.num_vertices(), [&](std::size_t b, std::size_t e) {
      for (std::size_t v = b; v != e; ++v) vertex_of_slot_[vs[v]] = static_cast<std::uint32_t>(v);
    });
    for_chunks(topo.num_edges(), [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i != e; ++i) {
        const Edge& ed = topo.edges()[i];
        edge_end_slots_[layout_.edge_slot[i]] = {vs[ed[0]], vs[ed[1]]};
      }
    });
    for_chunks(topo.num_faces(), [&](std::size_t b, std::size_t e) {
      for (std::size_t f = b; f != e; ++f) {
        const Triangle& t = topo.faces()[f];
        face_corner_slots_[layout_.face_slot[f]] = {vs[t[0]], vs[t[1]], vs[t[2]]};
      }
    });
    vertex_quarters_.resize(topo.num_vertices());
  }

  /// Zeroes the storage after resize() (which leaves it untouched) through `for_chunks`, a
  /// parallel loop (see first_touch in geometry/large_allocator.h).
  template <class ForChunks>
  void first_touch(const ForChunks& for_chunks) {
    detail::first_touch(vertex_quarters_, for_chunks);
  }

  /// Vertices [begin, end): their swept segments between the interleaved positions x0, x1,
  /// inflated by `min_distance`. Each range writes only its own vertices. `kept` (per vertex
  /// id; nullptr: none): vertices whose volumes already hold these positions' (the previous
  /// step's, same positions), left as they are.
  void update_vertices(const double* x0, const double* x1, double min_distance, std::size_t begin, std::size_t end,
                       const std::uint8_t* kept = nullptr) {
    for (std::size_t v = begin; v != end; ++v)
      if (!kept || !kept[v]) vertex_volumes(x0, x1, min_distance, v, layout_.vertex_slot[v]);
  }

  /// The same by slot ranges [begin, end) of the storage, for a step where every vertex
  /// moves: the volumes are then written in storage order (sequentially, not scattered by
  /// the layout). The same values as the updates by id. `visit(slot, quarters)` is then called
  /// for every slot of the range, updated or kept, with its volumes (a second consumer of
  /// the step's volumes reads them while they are in cache, not in a second pass).
  /// `keep(v, slot)`, asked once for every slot of the range (v: its vertex): true where the
  /// volumes already hold these positions', left as they are (like update_vertices' `kept`).
  /// `coarse` (nullptr: none): where the vector kernel, if the processor has it, writes the
  /// coarse volumes of the slots it updates (LaneKernels::vertex_quarters, its `coarse`, at
  /// slot indices): `visit` is then called for the kept slots only. It must write the same
  /// there as `visit` would (the coarse volumes of those quarters on that grid).
  /// `visit_kept` false: `visit` is not called for the kept slots (what it wrote for them
  /// before still holds).
  template <class Keep, class Visit>
  void update_vertex_slots_keeping(const double* x0, const double* x1, double min_distance, std::size_t begin,
                                   std::size_t end, const Keep& keep, const Visit& visit,
                                   const CoarseOut* coarse = nullptr, bool visit_kept = true) {
    if constexpr (BV::kSlabs == 9) {
      // in vector lanes where the processor has them (LaneKernels::vertex_quarters: the same
      // values), 64 slots at a time: which to keep first, then the volumes, then the visits
      if (const auto kernel = lane_kernels().vertex_quarters) {
        for (std::size_t g = begin; g < end; g += 64) {
          const std::size_t ge = std::min(end, g + 64);
          std::uint64_t kept = 0;
          for (std::size_t s = g; s != ge; ++s) kept |= std::uint64_t(keep(vertex_of_slot_[s], s)) << (s - g);
          CoarseOut here;
          if (coarse) here = {coarse->origin, coarse->scale, coarse->out + g};
          kernel(x0, x1, vertex_of_slot_.data() + g, ge - g, min_distance, kept, vertex_quarters_[g].bounds[0][0],
                 coarse ? &here : nullptr);
          for (std::size_t s = g; s != ge; ++s)
            if (!coarse || (visit_kept && (kept >> (s - g) & 1u))) visit(s, vertex_quarters_[s]);
        }
        return;
      }
    }
    constexpr std::size_t kAhead = 8;  // positions read a few slots ahead: the layout scatters them
    for (std::size_t s = begin; s != end; ++s) {
      if (s + kAhead < end) {
        const std::size_t a = 3 * std::size_t(vertex_of_slot_[s + kAhead]);
        __builtin_prefetch(x0 + a);
        __builtin_prefetch(x1 + a);
      }
      const std::uint32_t v = vertex_of_slot_[s];
      const bool kept = keep(v, s);
      if (!kept) vertex_volumes(x0, x1, min_distance, v, s);
      if (!kept || visit_kept) visit(s, vertex_quarters_[s]);
    }
  }
  /// The same with `kept` (per vertex id; nullptr: none) as keep().
  template <class Visit>
  void update_vertex_slots(const double* x0, const double* x1, double min_distance, std::size_t begin,
                           std::size_t end, const std::uint8_t* kept, const Visit& visit) {
    update_vertex_slots_keeping(
        x0, x1, min_distance, begin, end, [kept](std::uint32_t v, std::size_t) { return kept && kept[v]; }, visit);
  }
  void update_vertex_slots(const double* x0, const double* x1, double min_distance, std::size_t begin,
                           std::size_t end, const std::uint8_t* kept = nullptr) {
    update_vertex_slots(x0, x1, min_distance, begin, end, kept, [](std::size_t, const Quarters&) {});
  }
  /// A vertex's whole-step volume (the merge of its quarters).
  BV vertex(std::uint32_t v) const { return vertex_at(layout_.vertex_slot[v]); }
  /// A face's whole-step volume (merged on demand from its corners').
  BV face(std::uint32_t f) const { return face_at(layout_.face_slot[f]); }
  /// An edge's whole-step volume (merged on demand).
  BV edge(const Edge& e) const { return BV::merged(vertex(e[0]), vertex(e[1])); }

  const Quarters& vertex_quarters(std::uint32_t v) const { return vertex_quarters_[layout_.vertex_slot[v]]; }
  /// An edge's quarters (merged on demand from its ends').
  Quarters edge_quarters(std::uint32_t e) const { return edge_quarters_at(layout_.edge_slot[e]); }
  /// A face's quarters (merged on demand from its corners').
  Quarters face_quarters(const Triangle& t) const {
    Quarters q = Quarters::merged(vertex_quarters(t[0]), vertex_quarters(t[1]));
    q.merge(vertex_quarters(t[2]));
    return q;
  }

  /// The same by slot (VolumeLayout).
  BV vertex_at(std::uint32_t slot) const { return vertex_quarters_[slot].whole(); }
  BV face_at(std::uint32_t slot) const {
    Quarters q;
    face_quarters_into(slot, q);
    return q.whole();
  }
  const Quarters& vertex_quarters_at(std::uint32_t slot) const { return vertex_quarters_[slot]; }
  Quarters edge_quarters_at(std::uint32_t slot) const {
    const Edge& c = edge_end_slots_[slot];
    return Quarters::merged(vertex_quarters_[c[0]], vertex_quarters_[c[1]]);
  }
  /// The same into `q`.
  void edge_quarters_into(std::uint32_t slot, Quarters& q) const {
    const Edge& c = edge_end_slots_[slot];
    q.merge_of(vertex_quarters_[c[0]], vertex_quarters_[c[1]]);
  }
  /// The vertex slots of the corners of the face in face slot `slot`.
  const Triangle& face_corner_slots_at(std::uint32_t slot) const { return face_corner_slots_[slot]; }
  /// A face's quarters by face slot, into `q`.
  void face_quarters_into(std::uint32_t slot, Quarters& q) const {
    const Triangle& c = face_corner_slots_[slot];
    q.merge_of(vertex_quarters_[c[0]], vertex_quarters_[c[1]]);
    q.merge(vertex_quarters_[c[2]]);
  }
  /// The vertex slots of the ends of the edge in `slot`.
  const Edge& edge_end_slots_at(std::uint32_t slot) const { return edge_end_slots_[slot]; }

 private:
  /// Vertex v's volumes into slot `slot`: its swept segment between the interleaved positions
  /// x0, x1, inflated by `min_distance`.
  void vertex_volumes(const double* x0, const double* x1, double min_distance, std::size_t v, std::size_t slot) {
    constexpr int S = BV::kSlabs;
    const Vec3 a(x0[3 * v], x0[3 * v + 1], x0[3 * v + 2]);
    const Vec3 b(x1[3 * v], x1[3 * v + 1], x1[3 * v + 2]);
    // The segment's projections on the slabs' axes at t = k/4, k = 0..4: those of its ends,
    // and in between pa + (k/4)(pb - pa); each quarter's bounds moved out by quarter_margin and
    // rounded to the nearest float (quarter_volumes.h says why that holds the exact path).
    alignas(16) double pa[S + 1], pb[S + 1];
    BV::project(a, pa);
    BV::project(b, pb);
    pa[S] = pb[S] = 0;  // the second lane of the last pair when S is odd
    const double margin = quarter_margin(std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()), min_distance);
    Quarters& q = vertex_quarters_[slot];
    constexpr float kMax = std::numeric_limits<float>::max();
#if defined(__SSE2__)
    // Two slabs at a time: lane i of a register holds slab s + i.
    const __m128d m = _mm_set1_pd(margin);
    const __m128 big = _mm_set1_ps(kMax), low = _mm_set1_ps(-kMax);
    for (int s = 0; s < S; s += 2) {
      const __m128d p0 = _mm_load_pd(pa + s), p4 = _mm_load_pd(pb + s), d = _mm_sub_pd(p4, p0);
      const __m128d p1 = _mm_add_pd(p0, _mm_mul_pd(_mm_set1_pd(0.25), d));
      const __m128d p2 = _mm_add_pd(p0, _mm_mul_pd(_mm_set1_pd(0.5), d));
      const __m128d p3 = _mm_add_pd(p0, _mm_mul_pd(_mm_set1_pd(0.75), d));
      // Quarter k's bounds of both slabs, to float (round to nearest), then slab by slab.
      auto quarters = [](__m128d q0, __m128d q1, __m128d q2, __m128d q3, __m128& first, __m128& second) {
        const __m128 x = _mm_movelh_ps(_mm_cvtpd_ps(q0), _mm_cvtpd_ps(q1));  // s q0, s+1 q0, s q1, s+1 q1
        const __m128 y = _mm_movelh_ps(_mm_cvtpd_ps(q2), _mm_cvtpd_ps(q3));  // s q2, s+1 q2, s q3, s+1 q3
        first = _mm_shuffle_ps(x, y, _MM_SHUFFLE(2, 0, 2, 0));
        second = _mm_shuffle_ps(x, y, _MM_SHUFFLE(3, 1, 3, 1));
      };
      __m128 lo0, lo1, hi0, hi1;
      quarters(_mm_sub_pd(_mm_min_pd(p0, p1), m), _mm_sub_pd(_mm_min_pd(p1, p2), m),
               _mm_sub_pd(_mm_min_pd(p2, p3), m), _mm_sub_pd(_mm_min_pd(p3, p4), m), lo0, lo1);
      quarters(_mm_add_pd(_mm_max_pd(p0, p1), m), _mm_add_pd(_mm_max_pd(p1, p2), m),
               _mm_add_pd(_mm_max_pd(p2, p3), m), _mm_add_pd(_mm_max_pd(p3, p4), m), hi0, hi1);
      // past the float range: +inf below becomes the largest float, -inf above its negative
      _mm_store_ps(q.lo(s), _mm_min_ps(lo0, big));
      _mm_store_ps(q.hi(s), _mm_max_ps(hi0, low));
      if (s + 1 < S) {
        _mm_store_ps(q.lo(s + 1), _mm_min_ps(lo1, big));
        _mm_store_ps(q.hi(s + 1), _mm_max_ps(hi1, low));
      }
    }
#else
    for (int s = 0; s < S; ++s) {
      const double d = pb[s] - pa[s];
      const double p[5] = {pa[s], pa[s] + 0.25 * d, pa[s] + 0.5 * d, pa[s] + 0.75 * d, pb[s]};
      for (int k = 0; k < 4; ++k) {
        const float lo = static_cast<float>(std::min(p[k], p[k + 1]) - margin);
        const float hi = static_cast<float>(std::max(p[k], p[k + 1]) + margin);
        q.lo(s)[k] = lo < kMax ? lo : kMax;  // as _mm_min_ps(lo, big) and _mm_max_ps(hi, low)
        q.hi(s)[k] = hi > -kMax ? hi : -kMax;
      }
    }
#endif
  }

  VolumeLayout layout_;
  LargeVector<std::uint32_t> vertex_of_slot_;  ///< per vertex slot: the vertex
  LargeVector<Edge> edge_end_slots_;           ///< per edge slot: its ends' vertex slots
  LargeVector<Triangle> face_corner_slots_;    ///< per face slot: its corners' vertex slots
  // by slot:
  LargeVector<Quarters> vertex_quarters_;   ///< per vertex: its path over the quarters
};

}  // namespace mccd::detail
