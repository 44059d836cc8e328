#pragma once
/// @file Internal: the work at an overlapping leaf pair, the feature pairs it carries (the
/// canonical rule, core/carriers.h), each behind its feature-volume tests (whole step, then
/// halves and quarters) and the coplanarity filter (geometry/ccd_filter.h) restricted to the
/// quarters where the volumes meet, then the narrow phase, a template parameter (ipc-toolkit
/// passes its narrow phase the same way, at run time).
#include <cstdint>

#include <mccd/core/carriers.h>
#include <mccd/core/query.h>
#include <mccd/core/worker_output.h>
#include <bit>

#include <mccd/geometry/ccd.h>
#include <mccd/geometry/ccd_filter.h>
#include <mccd/geometry/swept_volumes.h>

namespace mccd::detail {

/// The default narrow phase: mccd's conservative elementary tests (geometry/ccd.h).
struct ConservativeCcd {
  CcdOptions options;
  bool vertex_face(const CcdPoints& p, double& toi, StepStats& s) const {
    return vertex_face_ccd(p, toi, options, &s.vf_ccd);
  }
  bool edge_edge(const CcdPoints& p, double& toi, StepStats& s) const {
    return edge_edge_ccd(p, toi, options, &s.ee_ccd);
  }
};

/// Reads the step's positions (interleaved doubles, global vertex ids), volumes and query state
/// through references owned by the stepper, so one object serves every step.
template <BoundingVolume BV, class NarrowPhase = ConservativeCcd>
class LeafPairs {
 public:
  LeafPairs(const MeshTopology& topo, const Carriers& carriers, const SweptVolumes<BV>& swept, const Positions& x0,
            const Positions& x1, QueryState& query, NarrowPhase narrow)
      : topo_(topo),
        carriers_(carriers),
        swept_(swept),
        x0_(x0),
        x1_(x1),
        query_(query),
        narrow_(narrow) {}

  /// Whether every triangle of one BVH leaf is adjacent to every triangle of the other: their
  /// features are all the orphan set's, so the leaf pair is skipped without a test.
  bool all_adjacent(const std::uint32_t* a, std::uint32_t na, const std::uint32_t* b, std::uint32_t nb) const {
    for (std::uint32_t i = 0; i < na; ++i)
      for (std::uint32_t j = 0; j < nb; ++j)
        if (!topo_.adjacent(a[i], b[j])) return false;
    return true;
  }

  /// Two overlapping BVH leaves: each non-adjacent pair of their triangles, behind the
  /// triangles' own volume test (skipped with one triangle per leaf, where the leaf volumes
  /// are the triangle volumes). Testing each triangle against the other leaf first does not
  /// pay: the triangles of overlapping leaves nearly always overlap the other leaf.
  /// `within`: the quarters in which the two leaves meet.
  void process_leaves(const std::uint32_t* a, std::uint32_t na, const std::uint32_t* b, std::uint32_t nb,
                      WorkerOutput& out, unsigned within = 0xF) const {
    if (na == 1 && nb == 1) {
      process(a[0], b[0], out);
      return;
    }
    if (too_late(within)) return;
    for (std::uint32_t i = 0; i < na; ++i)
      for (std::uint32_t j = 0; j < nb; ++j) process_if_overlapping(a[i], b[j], out, within);
  }

  /// A non-adjacent triangle pair (s, t) if their volumes overlap (adjacent pairs are skipped).
  void process_if_overlapping(std::uint32_t s, std::uint32_t t, WorkerOutput& out, unsigned within = 0xF) const {
    if (topo_.adjacent(s, t)) return;
    ++out.stats.triangle_tests;
    if (swept_.face(s).overlaps(swept_.face(t))) process(s, t, out, within);
  }

  /// The feature pairs carried by the non-adjacent, overlapping triangle pair (s, t).
  void process(std::uint32_t s, std::uint32_t t, WorkerOutput& out, unsigned within = 0xF) const {
    ++out.stats.leaf_pairs;
    // Every feature of s and t lies in its triangle during each piece of the step: when the
    // triangles' piece volumes never meet, no feature pair below can pass its own test.
    const unsigned quarters = swept_.faces_quarters(s, t, within);
    if (!quarters || too_late(quarters)) return;
    const Triangle& S = topo_.faces()[s];
    const Triangle& T = topo_.faces()[t];
    const Carriers::TriangleFirsts& fs = carriers_.firsts(s);
    const Carriers::TriangleFirsts& ft = carriers_.firsts(t);
    for (int k = 0; k < 3; ++k)
      if (carriers_.carries_vf(S[k], fs.corner[k], s, t)) test_vf(S[k], t, out, quarters);
    for (int k = 0; k < 3; ++k)
      if (carriers_.carries_vf(T[k], ft.corner[k], t, s)) test_vf(T[k], s, out, quarters);
    // The edges' quarter volumes are merged once per edge here, not once per edge pair.
    const auto& es = topo_.face_edges(s);
    const auto& et = topo_.face_edges(t);
    EdgePieces ps[3], pt[3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (carriers_.carries_ee(es[i], fs.edge[i], s, et[j], ft.edge[j], t)) {
          if (!ps[i].ready) ps[i].merge(swept_, topo_.edges()[es[i]], quarters);
          if (!pt[j].ready) pt[j].merge(swept_, topo_.edges()[et[j]], quarters);
          test_ee(es[i], et[j], ps[i].pieces, pt[j].pieces, out, quarters);
        }
  }

  /// Vertex v against face f, behind the feature-volume tests.
  /// `within`: the quarters where a triangle of v and f meet (from process()), all four
  /// otherwise; the feature's own quarters are a subset (its volumes lie inside the
  /// triangles'), so only those are tested and the mask is the same either way.
  void test_vf(std::uint32_t v, std::uint32_t f, WorkerOutput& out, unsigned within = 0xF) const {
    if (query_.stopped()) return;
    ++out.stats.feature_box_tests;
    if (!swept_.vertex(v).overlaps(swept_.face(f))) return;
    const unsigned pieces = swept_.vertex_face_quarters(v, f, within);
    if (!pieces) return;
    const Triangle& t = topo_.faces()[f];
    CcdPoints p;
    load({v, t[0], t[1], t[2]}, p);
    const unsigned quarters = coplanar_quarters(CcdKind::VertexFace, p, narrow_.options.min_distance, pieces);
    if (!quarters) {
      ++out.stats.vf_filtered;
      return;
    }
    if (!wanted(std::countr_zero(quarters), v, f, ContactKind::VertexFace, out)) return;
    ++out.stats.vf_tests;
    double toi = 0;
    if (narrow_.vertex_face(p, toi, out.stats)) hit({v, f, ContactKind::VertexFace, toi}, out);
  }

  /// Edges a and b (sharing no vertex), behind the feature-volume tests.
  void test_ee(std::uint32_t a, std::uint32_t b, WorkerOutput& out) const {
    EdgePieces pa, pb;
    pa.merge(swept_, topo_.edges()[a], 0xF);
    pb.merge(swept_, topo_.edges()[b], 0xF);
    test_ee(a, b, pa.pieces, pb.pieces, out, 0xF);
  }

  /// The same with the edges' quarter volumes already merged (at least the quarters of
  /// `within`).
  void test_ee(std::uint32_t a, std::uint32_t b, const PieceVolumes<BV>& pa, const PieceVolumes<BV>& pb,
               WorkerOutput& out, unsigned within) const {
    if (a > b) std::swap(a, b);
    ++out.stats.feature_box_tests;
    if (!swept_.edge(a).overlaps(swept_.edge(b))) return;
    const Edge& ea = topo_.edges()[a];
    const Edge& eb = topo_.edges()[b];
    const unsigned pieces = meeting_quarters([&](int q) { return pa[q].overlaps(pb[q]); }, within);
    if (!pieces) return;
    CcdPoints p;
    load({ea[0], ea[1], eb[0], eb[1]}, p);
    const unsigned quarters = coplanar_quarters(CcdKind::EdgeEdge, p, narrow_.options.min_distance, pieces);
    if (!quarters) {
      ++out.stats.ee_filtered;
      return;
    }
    if (!wanted(std::countr_zero(quarters), a, b, ContactKind::EdgeEdge, out)) return;
    ++out.stats.ee_tests;
    double toi = 0;
    if (narrow_.edge_edge(p, toi, out.stats)) hit({a, b, ContactKind::EdgeEdge, toi}, out);
  }

 private:
  /// An earliest-impact query skips what cannot meet before the best time found so far.
  bool too_late(unsigned quarters) const {
    return query_.kind() == StepKind::Earliest && 0.25 * std::countr_zero(quarters) >= query_.best();
  }

  /// An edge's quarter volumes: the merge of its two vertices' (only the quarters asked for).
  struct EdgePieces {
    PieceVolumes<BV> pieces;
    bool ready = false;
    void merge(const SweptVolumes<BV>& swept, const Edge& e, unsigned within) {
      const PieceVolumes<BV>&a = swept.vertex_pieces(e[0]), &b = swept.vertex_pieces(e[1]);
      for (int q = 0; q < 4; ++q)
        if (within >> q & 1u) pieces[q] = BV::merged(a[q], b[q]);
      ready = true;
    }
  };

  /// Whether a pair that passed its volume tests goes to the narrow phase. Earliest queries
  /// skip pairs that cannot meet before the best time found so far; candidate queries collect
  /// the pair instead, with the start of its first meeting quarter as the time.
  bool wanted(int quarter, std::uint32_t a, std::uint32_t b, ContactKind kind, WorkerOutput& out) const {
    switch (query_.kind()) {
      case StepKind::Full:
      case StepKind::FirstContact:
        return true;
      case StepKind::Earliest:
        return 0.25 * quarter < query_.best();
      case StepKind::Candidates:
        out.contacts.push_back({a, b, kind, 0.25 * quarter});
        return false;
    }
    return true;
  }

  void hit(const RawContact& c, WorkerOutput& out) const {
    out.contacts.push_back(c);
    if (query_.kind() != StepKind::Full) query_.found(c.toi);
  }

  void load(const std::array<std::uint32_t, 4>& ids, CcdPoints& p) const {
    for (int k = 0; k < 4; ++k) {
      p.start[k] = x0_.point(ids[k]);
      p.end[k] = x1_.point(ids[k]);
    }
  }

  const MeshTopology& topo_;
  const Carriers& carriers_;
  const SweptVolumes<BV>& swept_;
  const Positions& x0_;
  const Positions& x1_;
  QueryState& query_;
  NarrowPhase narrow_;
};

}  // namespace mccd::detail
