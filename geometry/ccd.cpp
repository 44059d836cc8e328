// The method of the elementary tests (the contract is in geometry/ccd.h):
//  (a) swept boxes: the axis-aligned boxes of each primitive over [0, 1] (exact comparisons);
//  (b) coplanarity filter: the cubic f(t) = det of the three difference vectors, in Bernstein
//      form over [0, 1] with a rigorous forward error bound; four coefficients of one sign
//      beyond the bound (beyond d * max|normal| when min_distance = d > 0) prove that the
//      points are never coplanar, hence never touch. Most pairs leave at (a) or (b);
//  (c0) min_distance = d > 0: pairs certainly within d at t = 0 (corner to corner, corner to
//      segment, or the interior case, with rigorous bounds; geometry/ccd_distance.h) are
//      contacts at toi = 0, without a search;
//  (c1) fast path (d = 0; geometry/ccd_fast.h): the roots of the cubic are isolated from its
//      Bernstein coefficients (Descartes' rule of signs, splitting at its critical points),
//      each bracketed within a few ulps of time by two evaluations of the cubic with
//      certain signs, and the inside functions at the bracket's ends bound them over it. A
//      root where some g_i is certainly negative has no contact; the first root where every
//      g_i is certainly positive is a certified contact (toi on the grid of 2^-32 below it).
//      Every root rejected: no contact. Where the roots cannot be isolated (the cubic within
//      its error bound at t = 0 or t = 1, as for primitives moving in one plane), one
//      separation test over [0, 1]. Then one try of the search's jump to a touch (below) on
//      [0, 1], with the cubic and the separation test clearing what lies before the window.
//      Anything undecided goes to the search, so the answer is the search's answer or a
//      better one (the fast path never reports a pair that does not touch). It decides
//      nearly every true contact of a real step and most pairs past (b);
//  (c) a depth-first search over dyadic time pieces, earliest first. On each piece the cubic
//      and the inside functions g_i (VF: the barycentric coordinates times |n|^2; EE: the
//      two segment parameters and their complements times |da x db|^2), all quartics in
//      Bernstein form with error bounds, are enclosed. A piece is cleared when the cubic is
//      certainly nonzero, or some g_i is certainly negative (d = 0), or a separating
//      direction (closest points, face normal, in-plane edge normals, da x db and its
//      in-plane normals) holds over the whole piece, checked rigorously. It is a certified
//      contact when the cubic certainly changes sign and every g_i is certainly positive.
//      Undecided pieces are halved; pieces still undecided at 2^-40 are handed to the same
//      search in long double (64-bit mantissa, error bounds ~2^11 times smaller) down to
//      2^-56, and what that leaves undecided to the same search in Quad (IEEE binary128,
//      113 bits, software arithmetic, ~2^60 times smaller) down to 2^-100: an edge end or a
//      vertex passing 1e-17 from the other primitive is told apart there. What stays
//      undecided is reported as a contact at the start of that piece.
//      Shortcuts (geometry/ccd_exact.h: exact predicates on the input doubles with
//      floating-point expansions, behind floating-point filters):
//       - touching exactly at t = 0 (exact coplanarity and inside tests at the start
//         positions) is certified at once: toi = 0;
//       - touching exactly at t = 1 is proved the same way on the end positions (lazily,
//         once, when the values at t = 1 allow it); then a piece reaching t = 1 whose earlier
//         part [lo, 1 - 2^-k] (k = 40, 24, 12) is certainly free of coplanarity ends the
//         search with toi = 1 - 2^-k, and any piece undecided at depth >= 16 ends it with
//         toi = its start (every earlier piece is cleared, so this is never late);
//       - on a piece where the cubic certainly changes sign, its sign change is located by
//         bracketed floating-point Newton steps and the piece is replaced by a window of
//         width 2^(k+1-D) (D the maximum depth of the pass, k = 3, 8 or 13) around it,
//         once the cubic is proved (rigorous bounds, polynomials restricted from [0, 1])
//         certainly nonzero on the rest of the piece: about D - k levels of bisection are
//         skipped;
//       - a piece undecided at 2^-20 or finer (or when the budget runs out) is offered to
//         an exact certificate of touching without crossing (geometry/ccd_touch.h), before
//         any long-double pass: the vertex (VF) or an edge end (EE) and the segment it
//         meets, with their six start and end points exactly coplanar (exact orient3d), the
//         point crossing the segment's line strictly inside the segment within the piece or
//         [lo, lo + 2^-30] or [lo, lo + 2^-20] (rigorous bounds on three quadratics). A
//         certified touch is a contact at toi = the piece's start;
//       - on pieces at depths 0, 4, 8, 12 and 16, the same certificate is offered a window
//         [a, a + 2^-20] (on the grid of 2^-20, a >= the piece's start) around where a point
//         crosses a segment's line (the point-segment pairs in turn); when it certifies a
//         touch there and [start, a] is cleared in one piece by the tests of any piece, the
//         search ends with toi = a (the first contact lies in the window): the primitives
//         that move in one plane reach their touch in a few pieces instead of bisecting down
//         to 2^-20;
//       - piece budgets: 600 pieces in double, 64 in long double, 16 in Quad per query; a
//         query that exhausts them is reported as a contact at the start of the current
//         piece. Real steps decide nearly every pair in the fast path; the budgets bound the
//         cost of near-degenerate pairs (a Quad piece costs about 4 us, a double one 0.1 us).
//
// Elementary CCD tests (vertex-face, edge-edge) under linear motion: the entry points and
// stage (a). See geometry/ccd.h for the contract; the error analysis sits beside each stage
// (ccd_bernstein.h, ccd_stages.h, ccd_distance.h, ccd_fast.h, ccd_search.h).
#include <mccd/geometry/ccd.h>
#include <mccd/geometry/assert.h>

#include <mccd/geometry/ccd_detail.h>
#include <mccd/geometry/ccd_distance.h>
#include <mccd/geometry/ccd_fast.h>
#include <mccd/geometry/ccd_filter.h>

namespace mccd {
namespace detail {

namespace {

// Stage (a) for a kind known at compile time; when the boxes overlap, `mx` receives the largest
// absolute coordinate of the eight points (for the scaling in `load`), from the same minima
// and maxima. fl(lo2 - hi1) > d (1 + 4u) implies lo2 - hi1 > d; for d = 0 the sign of a
// rounded difference is exact.
template <CcdKind K>
bool box_overlap(const CcdPoints& p, double min_distance, double& mx) {
  constexpr int split = K == CcdKind::VertexFace ? 1 : 2;
  const double d = min_distance > 0 ? min_distance * (1 + 4 * kU) : 0.0;
  mx = 0;
  for (int ax = 0; ax < 3; ++ax) {
    double lo1 = std::min(p.start[0][ax], p.end[0][ax]), hi1 = std::max(p.start[0][ax], p.end[0][ax]);
    double lo2 = std::min(p.start[3][ax], p.end[3][ax]), hi2 = std::max(p.start[3][ax], p.end[3][ax]);
    for (int i = 1; i < 3; ++i) {
      const double a = p.start[i][ax], b = p.end[i][ax];
      double& lo = i < split ? lo1 : lo2;
      double& hi = i < split ? hi1 : hi2;
      lo = std::min(lo, std::min(a, b)), hi = std::max(hi, std::max(a, b));
    }
    if (lo2 - hi1 > d || lo1 - hi2 > d) return false;
    mx = std::max(mx, std::max(std::max(-lo1, -lo2), std::max(hi1, hi2)));
  }
  return true;
}

/// Stages (a) and (b) into `S`: Continue when the test must go on to stage (c); otherwise the
/// answer is final (Miss, or Hit with `toi`).
enum class Prepared { Continue, Miss, Hit, HitUnsafe };

/// `box`: run stage (a) first; without it, the caller's own volume tests stand for it.
template <CcdKind K>
Prepared prepare(const CcdPoints& p, double d, Setup<double>& S, double& toi, CcdCounters* counters, bool box = true) {
  if (counters) ++counters->queries;
  double mx = 0;
  if (box && !box_overlap<K>(p, d, mx)) {
    if (counters) ++counters->box_culled;
    return Prepared::Miss;
  }
  if (!box) mx = max_abs_coordinate(p);
  S.kind = K;
  switch (load(p, d, S, mx)) {
    case Load::Ok:
      break;
    case Load::AllZero:  // every point at the origin at both times: touching throughout
      toi = 0;
      if (counters) ++counters->hits;
      return Prepared::Hit;
    case Load::Unsafe:  // non-finite input or a dynamic range beyond 2^1000: conservative
      toi = 0;
      if (counters) ++counters->fallbacks, ++counters->hits;
      return Prepared::HitUnsafe;
  }
  coplanarity_of<K>(S);
  if (definite_sign(S.f, S.ef + S.dN) != 0) {
    if (counters) ++counters->coplanar_culled;
    return Prepared::Miss;
  }
  return Prepared::Continue;
}

/// Stage (c) on a prepared query.
template <CcdKind K>
bool finish(const CcdPoints& p, double d, Setup<double>& S, double& toi, CcdCounters* counters, CcdPath path) {
  using Kind = KindOps<K>;
  if (counters) ++counters->root_tests;
  pairs_of<K>(S);
  if (d > 0 && within_at_start<Kind>(S)) {
    toi = 0;  // within the minimum distance from the start
    if (counters) ++counters->hits;
    return true;
  }
  // Undecided by the fast path, which tried the separation test on all of [0, 1].
  bool fast_undecided = false;
  if (!(d > 0) && path == CcdPath::Fast) {
    const Fast r = fast_decide<Kind>(S, toi);
    if (r == Fast::Hit) {
      if (counters) ++counters->fast_hits, ++counters->hits;
      return true;
    }
    if (r == Fast::Miss) {
      if (counters) ++counters->fast_misses;
      return false;
    }
    fast_undecided = true;
  }
  Piece<double> root;
  root.lo = 0, root.hi = 1, root.depth = 0, root.f = S.f, root.ef = S.ef;
  TouchCertificate touch(S);
  // A touch in one plane (a vertex through an edge of the face, an edge end through the other
  // edge), where the fast path finds the cubic's root but cannot sign the inside functions
  // there: the search's first jump to a touch, before the inside functions are set up, with
  // the cubic and the separation test alone clearing what lies before it.
  if (fast_undecided && touch_in_window(S, touch, root, 0, 0.0, 1.0, toi)) {
    if (counters) ++counters->touches, ++counters->hits;
    return true;
  }
  double t = 0;
  const int ng = setup_inside(S, root);
  // Touching exactly at t = 0 (exact predicate on the input doubles): toi = 0 at once. Only
  // tried when the floating-point values at t = 0 allow it (coplanar and inside within
  // their error bounds).
  if (may_touch_at(root, ng, 0) &&
      (K == CcdKind::VertexFace ? exact_vertex_face_touch(p.start) : exact_edge_edge_touch(p.start))) {
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
  lp.whole_not_separated = fast_undecided;
  lp.touch = &touch;
  const Outcome r = search(S, root, root, ng, kCcdMaxDepth, budget, t, &lp);
  if (counters) counters->pieces +=
      (kCcdPieceBudget - budget) + (kCcdPieceBudgetLong - lp.wide.budget) + (kCcdPieceBudgetQuad - lp.quad.budget);
  if (r == Outcome::Miss) return false;
  toi = t;
  if (counters) ++counters->hits;
  return true;
}

template <CcdKind K>
bool run(const CcdPoints& p, double& toi, const CcdOptions& options, CcdCounters* counters, CcdPath path) {
  const double d = options.min_distance > 0 ? options.min_distance : 0.0;
  Setup<double> S;
  switch (prepare<K>(p, d, S, toi, counters)) {
    case Prepared::Miss: return false;
    case Prepared::Hit:
    case Prepared::HitUnsafe: return true;
    case Prepared::Continue: break;
  }
  return finish<K>(p, d, S, toi, counters, path);
}

/// The quarters of `within` in which the prepared cubic S.f may vanish (within the distance
/// margin): a definite sign of every Bernstein coefficient beyond the error bound (plus the
/// margin) proves the cubic nonzero on the whole closed piece (the convex hull property).
unsigned quarters_of(const Setup<double>& S, unsigned within) {
  Bern<3, double> h[2], q[4];
  const double eh = split_half(S.f, S.ef, h[0], h[1]);
  unsigned mask = 0;
  for (int i = 0; i < 2; ++i) {
    const unsigned half = within >> (2 * i) & 3u;
    if (!half || definite_sign(h[i], eh + S.dN) != 0) continue;
    const double eq = split_half(h[i], eh, q[2 * i], q[2 * i + 1]);
    for (int j = 0; j < 2; ++j)
      if ((half >> j & 1u) && definite_sign(q[2 * i + j], eq + S.dN) == 0) mask |= 1u << (2 * i + j);
  }
  return mask;
}

}  // namespace

bool FilteredCcd::start(CcdKind kind, const CcdPoints& p, double min_distance, unsigned within, unsigned& decided) {
  kind_ = kind;
  points_ = &p;
  d_ = min_distance > 0 ? min_distance : 0.0;
  const Prepared r = kind == CcdKind::VertexFace ? prepare<CcdKind::VertexFace>(p, d_, S_, toi_, nullptr, false)
                                                 : prepare<CcdKind::EdgeEdge>(p, d_, S_, toi_, nullptr, false);
  state_ = static_cast<int>(r);
  switch (r) {
    case Prepared::Miss:
      decided = 0;
      return false;
    case Prepared::Hit:
    case Prepared::HitUnsafe:
      decided = within;  // not analysed: every quarter asked for
      return false;
    case Prepared::Continue:
      break;
  }
  return true;
}

unsigned FilteredCcd::filter(CcdKind kind, const CcdPoints& p, double min_distance, unsigned within) {
  unsigned decided = 0;
  return start(kind, p, min_distance, within, decided) ? quarters_of(S_, within) : decided;
}

unsigned FilteredCcd::filter_known(CcdKind kind, const CcdPoints& p, unsigned within, unsigned known) {
  unsigned decided = 0;
  if (!start(kind, p, 0.0, within, decided)) return decided;
  MCCD_ASSERT(quarters_of(S_, within) == (known & within), "the vector filter decides each quarter as the filter");
  return known & within;
}

bool FilteredCcd::test(double& toi, CcdCounters* counters) {
  switch (static_cast<Prepared>(state_)) {
    case Prepared::Miss: return false;  // not reached after a filter that returned non-zero
    case Prepared::Hit:
    case Prepared::HitUnsafe:
      // the counts prepare() would have made
      if (counters) {
        ++counters->queries, ++counters->hits;
        if (static_cast<Prepared>(state_) == Prepared::HitUnsafe) ++counters->fallbacks;
      }
      toi = toi_;
      return true;
    case Prepared::Continue: break;
  }
  if (counters) ++counters->queries;
  return kind_ == CcdKind::VertexFace
             ? finish<CcdKind::VertexFace>(*points_, d_, S_, toi, counters, CcdPath::Fast)
             : finish<CcdKind::EdgeEdge>(*points_, d_, S_, toi, counters, CcdPath::Fast);
}

bool ccd_box_overlap(CcdKind kind, const CcdPoints& p, double min_distance) {
  double mx;
  return kind == CcdKind::VertexFace ? box_overlap<CcdKind::VertexFace>(p, min_distance, mx)
                                     : box_overlap<CcdKind::EdgeEdge>(p, min_distance, mx);
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
  return kind == CcdKind::VertexFace ? run<CcdKind::VertexFace>(p, toi, options, counters, path)
                                     : run<CcdKind::EdgeEdge>(p, toi, options, counters, path);
}

}  // namespace detail

bool vertex_face_ccd(const CcdPoints& p, double& toi, const CcdOptions& options, CcdCounters* counters) {
  return detail::run<detail::CcdKind::VertexFace>(p, toi, options, counters, detail::CcdPath::Fast);
}

bool edge_edge_ccd(const CcdPoints& p, double& toi, const CcdOptions& options, CcdCounters* counters) {
  return detail::run<detail::CcdKind::EdgeEdge>(p, toi, options, counters, detail::CcdPath::Fast);
}

}  // namespace mccd
