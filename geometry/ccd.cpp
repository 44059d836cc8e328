// Elementary CCD tests (vertex-face, edge-edge) under linear motion: the entry points and
// stage (a). See geometry/ccd.h for the contract; the error analysis sits beside each stage
// (ccd_bernstein.h, ccd_stages.h, ccd_search.h).
#include <mccd/geometry/ccd.h>

#include <mccd/geometry/ccd_detail.h>
#include <mccd/geometry/ccd_distance.h>
#include <mccd/geometry/ccd_fast.h>

namespace mccd {
namespace detail {

bool ccd_box_overlap(CcdKind kind, const CcdPoints& p, double min_distance) {
  const int split = kind == CcdKind::VertexFace ? 1 : 2;
  // fl(lo2 - hi1) > d (1 + 4u) implies lo2 - hi1 > d; for d = 0 the sign of a rounded
  // difference is exact.
  const double d = min_distance > 0 ? min_distance * (1 + 4 * kU) : 0.0;
  for (int ax = 0; ax < 3; ++ax) {
    double lo1 = HUGE_VAL, hi1 = -HUGE_VAL, lo2 = HUGE_VAL, hi2 = -HUGE_VAL;
    for (int i = 0; i < 4; ++i) {
      const double a = p.start[i][ax], b = p.end[i][ax];
      const double mn = std::min(a, b), mx = std::max(a, b);
      if (i < split) {
        lo1 = std::min(lo1, mn), hi1 = std::max(hi1, mx);
      } else {
        lo2 = std::min(lo2, mn), hi2 = std::max(hi2, mx);
      }
    }
    if (lo2 - hi1 > d || lo1 - hi2 > d) return false;
  }
  return true;
}

bool ccd_coplanarity_may_hit(CcdKind kind, const CcdPoints& p, double min_distance) {
  Setup<double> S;
  S.kind = kind;
  if (load(p, min_distance, S) != Load::Ok) return true;
  coplanarity(S);
  return definite_sign(S.f, S.ef + S.dN) == 0;
}

bool ccd_run(CcdKind kind, const CcdPoints& p, double& toi, const CcdOptions& options, CcdCounters* counters,
             CcdPath path) {
  if (counters) ++counters->queries;
  const double d = options.min_distance > 0 ? options.min_distance : 0.0;
  if (!ccd_box_overlap(kind, p, d)) {
    if (counters) ++counters->box_culled;
    return false;
  }
  Setup<double> S;
  S.kind = kind;
  switch (load(p, d, S)) {
    case Load::Ok:
      break;
    case Load::AllZero:  // every point at the origin at both times: touching throughout
      toi = 0;
      if (counters) ++counters->hits;
      return true;
    case Load::Unsafe:  // non-finite input or a dynamic range beyond 2^1000: conservative
      toi = 0;
      if (counters) ++counters->fallbacks, ++counters->hits;
      return true;
  }
  coplanarity(S);
  if (definite_sign(S.f, S.ef + S.dN) != 0) {
    if (counters) ++counters->coplanar_culled;
    return false;
  }
  if (counters) ++counters->root_tests;
  if (d > 0 && (kind == CcdKind::VertexFace ? within_at_start<KindOps<CcdKind::VertexFace>>(S)
                                            : within_at_start<KindOps<CcdKind::EdgeEdge>>(S))) {
    toi = 0;  // within the minimum distance from the start
    if (counters) ++counters->hits;
    return true;
  }
  if (!(d > 0) && path == CcdPath::Fast) {
    const Fast r = kind == CcdKind::VertexFace ? fast_decide<KindOps<CcdKind::VertexFace>>(S, toi)
                                               : fast_decide<KindOps<CcdKind::EdgeEdge>>(S, toi);
    if (r == Fast::Hit) {
      if (counters) ++counters->fast_hits, ++counters->hits;
      return true;
    }
    if (r == Fast::Miss) {
      if (counters) ++counters->fast_misses;
      return false;
    }
  }
  double t = 0;
  Piece<double> root;
  root.lo = 0, root.hi = 1, root.depth = 0, root.f = S.f;
  const int ng = setup_inside(S, root);
  // Touching exactly at t = 0 (exact predicate on the input doubles): toi = 0 at once. Only
  // tried when the floating-point values at t = 0 allow it (coplanar and inside within
  // their error bounds).
  if (may_touch_at(root, ng, 0) &&
      (kind == CcdKind::VertexFace ? exact_vertex_face_touch(p.start) : exact_edge_edge_touch(p.start))) {
    toi = 0;
    if (counters) ++counters->hits;
    return true;
  }
  int budget = kCcdPieceBudget;
  LongPass lp;
  lp.S = &S;
  lp.counters = counters;
  lp.points = &p;
  lp.root_d = &root;
  lp.ng_d = ng;
  const Outcome r = search(S, root, root, ng, kCcdMaxDepth, budget, t, &lp);
  if (counters) counters->pieces += (kCcdPieceBudget - budget) + (kCcdPieceBudgetLong - lp.budget);
  if (r == Outcome::Miss) return false;
  toi = t;
  if (counters) ++counters->hits;
  return true;
}

}  // namespace detail

bool vertex_face_ccd(const CcdPoints& p, double& toi, const CcdOptions& options, CcdCounters* counters) {
  return detail::ccd_run(detail::CcdKind::VertexFace, p, toi, options, counters);
}

bool edge_edge_ccd(const CcdPoints& p, double& toi, const CcdOptions& options, CcdCounters* counters) {
  return detail::ccd_run(detail::CcdKind::EdgeEdge, p, toi, options, counters);
}

}  // namespace mccd
