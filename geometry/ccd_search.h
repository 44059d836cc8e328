#pragma once
/// @file Internal: stage (c) of the elementary CCD tests, the certified search over dyadic time
/// pieces, earliest first (the contract and the shortcuts are documented in geometry/ccd.h).
#include <type_traits>

#include <mccd/geometry/ccd_exact.h>
#include <mccd/geometry/ccd_stages.h>
#include <mccd/geometry/ccd_touch.h>

namespace mccd::detail {

// The earliest point of [lo, hi] where the cubic may be within `band` of 0 (|f| <= dN: the
// points within the minimum distance of coplanar; 0 without one), given that it certainly
// vanishes in [lo, hi] (opposite certain signs at the ends): bisect, keeping the left half
// unless the cubic is certainly beyond the band on it. No contact (within the minimum
// distance) lies before the point returned: never late.
template <class T>
T refine_toi(Bern<3, T> f, T ef, T lo, T hi, int depth, int max_depth, T band = T(0)) {
  while (depth < max_depth) {
    Bern<3, T> l, r;
    const T e = split_half(f, ef, l, r);
    const T mid = (lo + hi) / 2;
    if (definite_sign(l, e + band) != 0) {
      f = r;
      lo = mid;
    } else {
      f = l;
      hi = mid;
    }
    ef = e;
    ++depth;
  }
  return lo;
}

enum class Outcome { Miss, Hit, Undecided };

// Room for a depth-first search over pieces in T down to its pass's maximum depth (each level
// adds at most one entry).
template <class T>
inline constexpr int kStackDepth = (std::is_same_v<T, Quad> ? kCcdMaxDepthQuad : kCcdMaxDepthLong) + 4;

// On a piece where every inside function is certainly positive, contact happens exactly at
// the roots of the cubic: search them alone (earliest first). Miss: the cubic is certainly
// nonzero on the piece. Hit: a certain sign change; toi = the earliest point where the cubic
// may vanish. Undecided: an uncertain subpiece at max_depth; toi = its start.
template <class T>
Outcome cubic_roots(const Piece<T>& P, T dN, int max_depth, int& budget, T& toi) {
  struct Item {
    Bern<3, T> f;
    T ef, lo, hi;
    int depth;
  };
  Item st[kStackDepth<T>];
  int top = 0;
  st[top++] = {P.f, P.ef, P.lo, P.hi, P.depth};
  while (top > 0) {
    const Item I = st[--top];
    if (definite_sign(I.f, I.ef + dN) != 0) continue;
    const T c0 = I.f.c[0], c3 = I.f.c[3];
    if ((c0 > I.ef && c3 < -I.ef) || (c0 < -I.ef && c3 > I.ef)) {
      // With d > 0 the first time within d may precede the coplanar time: the earliest point
      // of the piece where the points may be within d of coplanar (the piece's start before:
      // 0 for a pair decided on the whole step, however late it met).
      toi = refine_toi(I.f, I.ef, I.lo, I.hi, I.depth, kCcdToiDepth, dN);
      return Outcome::Hit;
    }
    if (I.depth >= max_depth || --budget <= 0) {
      toi = I.lo;
      return Outcome::Undecided;
    }
    Item& R = st[top++];
    Item& L = st[top++];
    L.ef = R.ef = split_half(I.f, I.ef, L.f, R.f);
    L.lo = I.lo, L.hi = R.lo = (I.lo + I.hi) / 2, R.hi = I.hi;
    L.depth = R.depth = I.depth + 1;
  }
  return Outcome::Miss;
}


// Shortcut of the bisection on a piece P where the cubic certainly changes sign and nothing
// else is decided: locate the sign change (safeguarded Newton on f, root_estimate; any
// estimate is sound), take the window W of width 16 h around it (h = 2^-max_depth, W on the
// grid of h, so every bound used below is exact in T and 1 - lo, 1 - hi are exact), and
// prove with rigorous bounds (the polynomials restricted from the root piece) that the
// cubic is certainly nonzero (beyond d |n|) on P left and right of W: no contact there.
// Then W, with every polynomial restricted to it, replaces P; it lies where P would have
// been bisected to after about max_depth - 4 levels. False (nothing changed) when the proof
// fails.
template <class T>
bool jump_to_root(const Piece<T>& R, const Piece<T>& P, int ng, T dN, int max_depth, Piece<T>& W) {
  const T c0 = P.f.c[0], c3 = P.f.c[3];
  if (!((c0 > P.ef && c3 < -P.ef) || (c0 < -P.ef && c3 > P.ef))) return false;
  const T h = pow2<T>(-max_depth);
  const T width = P.hi - P.lo;
  if (width <= pow2<T>(6 - max_depth)) return false;
  T slope;
  const T ts = root_estimate(P.f, P.lo, P.hi, slope);
  // Window half-widths 8 h, 256 h, 8192 h: the uncertainty of the sign change may be wider
  // than a few h when the error bounds are large against the slope of the cubic.
  T a = 0, b = 0;
  int k = 3;
  for (; k <= 13; k += 5) {
    const T m = pow2<T>(k);
    a = std::max(P.lo, floor_(ts / h - m) * h);
    b = std::min(P.hi, a + 2 * m * h);
    if (!(a > P.lo || b < P.hi) || !(a < b)) return false;
    Bern<3, T> side;
    if (a > P.lo && definite_sign(side, restrict_to(R.f, R.ef, P.lo, a, side) + dN) == 0) continue;
    if (b < P.hi && definite_sign(side, restrict_to(R.f, R.ef, b, P.hi, side) + dN) == 0) continue;
    break;
  }
  if (k > 13) return false;
  W.lo = a, W.hi = b, W.depth = std::max(P.depth + 1, max_depth - k - 1);
  W.ef = restrict_to(R.f, R.ef, a, b, W.f);
  for (int i = 0; i < ng; ++i) W.eg[i] = restrict_to(R.g[i], R.eg[i], a, b, W.g[i]);
  return true;
}

// Depth-first search over dyadic time pieces, earliest first. A piece is cleared when the
// cubic is certainly nonzero on it, or (d = 0) some inside function is certainly negative,
// or a separating direction holds over it. A piece is a certified hit when the cubic
// certainly changes sign over it and every inside function is certainly positive.
// Undecided pieces are halved down to max_depth; the first undecided one at max_depth (or
// when the piece budget is spent) ends the search as Undecided with toi = its start.
// At t = 0 (end = 0) or t = 1 (end = 1) of the root piece: the cubic is zero and every inside
// function is >= 0 within the error bounds (a necessary condition of touching there).
inline bool may_touch_at(const Piece<double>& R, int ng, int end) {
  if (!(std::fabs(R.f.c[end * 3]) <= R.ef)) return false;
  for (int i = 0; i < ng; ++i)
    if (!(R.g[i].c[end * 4] >= -R.eg[i])) return false;
  return true;
}

// No contact in [lo, a] (a on the grid of 2^-20, so 1 - a is exact): the cubic certainly
// nonzero, or (d = 0) an inside function certainly negative, or a separating direction, over
// the whole of it, with the polynomials restricted from the root piece.
inline bool clear_before(const Setup<double>& S, const Piece<double>& root, int ng, double lo, double a) {
  if (!(a > lo)) return true;
  Bern<3, double> f;
  if (definite_sign(f, restrict_to(root.f, root.ef, lo, a, f) + S.dN) != 0) return true;
  for (int i = 0; i < ng; ++i) {
    Bern<4, double> g;
    if (definite_sign(g, restrict_to(root.g[i], root.eg[i], lo, a, g)) < 0) return true;
  }
  return separated(S, lo, a);
}

// A jump to a touch on [lo, hi] (for primitives moving in one plane, where the cubic clears
// nothing): a window [a, a + 2^-20] with a certified touch, and [lo, a] cleared in one piece by
// the tests of any piece (`root` with `ng` inside functions; 0: the cubic and the separation
// alone). No contact lies before a, so toi = a is not late and at most 2^-20 early.
inline bool touch_in_window(const Setup<double>& S, TouchCertificate& certificate, const Piece<double>& root, int ng,
                            double lo, double hi, double& toi) {
  for (int c = 0; c < certificate.num_pairs(); ++c) {
    const double a = certificate.window_from(c, lo, hi);
    if (a >= 0 && clear_before(S, root, ng, lo, a)) {
      toi = a;
      return true;
    }
  }
  return false;
}

// The long-double pass has no touch certificate (its pieces come from the double pass's).
struct NoTouchCertificate {
  template <class Setup>
  explicit NoTouchCertificate(const Setup&) {}
};

struct LongPass;
inline Outcome resolve_long(LongPass& lp, double lo, double hi, int depth, double& toi);
inline bool touches_at_end(LongPass& lp);
inline void count_touch(LongPass* lp);
inline bool whole_not_separated(const LongPass& lp);
// The query's certificate, when the caller made one (its pairs prepared once), else `own`.
inline TouchCertificate& certificate_of(LongPass* lp, TouchCertificate& own);
inline NoTouchCertificate& certificate_of(LongPass*, NoTouchCertificate& own) { return own; }

template <class T>
Outcome search(const Setup<T>& S, const Piece<T>& root, const Piece<T>& start, int ng, int max_depth, int& budget,
               T& toi, LongPass* long_pass) {
  Piece<T> stack[kStackDepth<T>];
  int top = 0;
  stack[top++] = start;
  const bool use_inside = !(S.d > 0);
  [[maybe_unused]] std::conditional_t<std::is_same_v<T, double>, TouchCertificate, NoTouchCertificate> own(S);
  [[maybe_unused]] auto& certificate = certificate_of(long_pass, own);
  while (top > 0) {
    const Piece<T> P = stack[--top];
    --budget;
    if (definite_sign(P.f, P.ef + S.dN) != 0) continue;
    bool excluded = false, all_positive = true;
    for (int i = 0; i < ng; ++i) {
      const int sg = definite_sign(P.g[i], P.eg[i]);
      if (sg < 0 && use_inside) excluded = true;
      all_positive = all_positive && sg > 0;
    }
    if (excluded) continue;
    if constexpr (std::is_same_v<T, double>) {
      // A proved touch at t = 1 and a piece reaching t = 1: when the cubic is certainly
      // nonzero on [lo, 1 - 2^-k], the first contact lies in [1 - 2^-k, 1]; toi = 1 - 2^-k.
      if (P.hi == 1 && long_pass && touches_at_end(*long_pass)) {
        for (const int k : {40, 24, 12}) {
          const double b = 1 - std::ldexp(1.0, -k);
          if (!(b > P.lo)) continue;
          Bern<3, T> side;
          if (definite_sign(side, restrict_to(root.f, root.ef, P.lo, b, side) + S.dN) != 0) {
            toi = b;
            return Outcome::Hit;
          }
        }
      }
    }
    if (all_positive) {
      // Every g > 0: contact exactly at the roots of the cubic in the piece.
      int md = max_depth;
      bool end_touch = false;
      if constexpr (std::is_same_v<T, double>) {
        end_touch = long_pass && touches_at_end(*long_pass);
        if (end_touch) md = std::max(P.depth, std::min(max_depth, kCcdCertDepth));
      }
      Outcome r = cubic_roots(P, S.dN, md, budget, toi);
      if constexpr (std::is_same_v<T, double>) {
        // A certain touch at t = 1 makes any undecided piece a contact (toi = its start).
        if (r == Outcome::Undecided && end_touch) return Outcome::Hit;
        if (r == Outcome::Undecided && long_pass && budget > 0) r = resolve_long(*long_pass, P.lo, P.hi, P.depth, toi);
      }
      if (r == Outcome::Miss) continue;
      return r;
    }
    // The separation test is the most expensive one: tried at every third level only, and
    // not again on [0, 1] when the fast path has tried it there.
    const bool tried = long_pass && whole_not_separated(*long_pass) && P.lo == 0 && P.hi == 1;
    if ((P.depth % 3 == 0 || P.depth >= max_depth - 1) && !tried && separated(S, P.lo, P.hi)) continue;
    if constexpr (std::is_same_v<T, double>) {
      // Every earlier piece is cleared; with a proved touch at t = 1, the first contact lies
      // in [lo, 1]: report it at lo instead of bisecting further.
      if (P.depth >= kCcdCertDepth && long_pass && touches_at_end(*long_pass)) {
        toi = P.lo;
        return Outcome::Hit;
      }
    }
    if constexpr (std::is_same_v<T, double>) {
      // A jump to a touch, tried where a jump to a root would be; a pair without a planar
      // certificate costs its exact part once per query.
      if (use_inside && P.depth < kCcdTouchDepth && P.depth % 4 == 0 &&
          touch_in_window(S, certificate, root, ng, P.lo, P.hi, toi)) {
        count_touch(long_pass);
        return Outcome::Hit;
      }
    }
    if constexpr (std::is_same_v<T, double>) {
      // A touch without crossing, certified exactly (geometry/ccd_touch.h), tried on pieces
      // of 2^-20 and finer (so toi is at most 2^-20 early, as for a window past the piece): a
      // contact in a window starting at lo, and every earlier piece is cleared, so toi = lo
      // is not late.
      if ((P.depth >= kCcdTouchDepth || budget <= 0) && certificate.certify(P.lo, P.hi)) {
        count_touch(long_pass);
        toi = P.lo;
        return Outcome::Hit;
      }
    }
    if (P.depth >= max_depth || budget <= 0) {
      if constexpr (std::is_same_v<T, double>) {
        // Second opinion in extended precision on this piece only.
        if (long_pass && budget > 0) {
          const Outcome r = resolve_long(*long_pass, P.lo, P.hi, P.depth, toi);
          if (r == Outcome::Miss) continue;
          return r;
        }
      }
      // Every earlier piece was cleared, so lo is never later than the first contact.
      toi = P.lo;
      return Outcome::Undecided;
    }
    if (P.depth % 4 == 0 && jump_to_root(root, P, ng, S.dN, max_depth, stack[top])) {
      ++top;
      continue;
    }
    Piece<T>& R = stack[top++];
    Piece<T>& L = stack[top++];
    const T mid = (P.lo + P.hi) / 2;
    L.lo = P.lo, L.hi = mid, R.lo = mid, R.hi = P.hi;
    L.depth = R.depth = P.depth + 1;
    L.ef = R.ef = split_half(P.f, P.ef, L.f, R.f);
    for (int i = 0; i < ng; ++i) L.eg[i] = R.eg[i] = split_half(P.g[i], P.eg[i], L.g[i], R.g[i]);
  }
  return Outcome::Miss;
}

// Largest double <= x.
template <class T>
inline double round_down(T x) {
  double r = static_cast<double>(x);
  if (static_cast<T>(r) > x) r = std::nextafter(r, -HUGE_VAL);
  return r;
}

// A pass in a wider scalar T (long double, where it is wider than double, with error bounds
// about 2^11 times smaller; then Quad) over the pieces the double search left undecided at its
// maximum depth: the same search, on the query's setup in T (from the double one's scaled
// points, exactly), built on first use.
template <class T>
struct WidePass {
  bool ready = false;
  Setup<T> S;
  Piece<T> root;
  int ng = 0;
  int budget;
  explicit WidePass(int b) : budget(b) {}
  void prepare(const Setup<double>& D) {
    if (ready) return;
    S.kind = D.kind;
    S.d = D.d;
    for (int i = 0; i < 4; ++i) {
      S.s[i] = {D.s[i].x, D.s[i].y, D.s[i].z};
      S.e[i] = {D.e[i].x, D.e[i].y, D.e[i].z};
    }
    coplanarity(S);
    root.f = S.f;
    ng = setup_inside(S, root);
    ready = true;
  }
  // The search of [lo, hi] in T, down to `max_depth`.
  Outcome run(double lo, double hi, int depth, int max_depth, T& toi) {
    Piece<T> P;
    P.lo = lo, P.hi = hi, P.depth = depth;
    P.ef = restrict_to(root.f, root.ef, P.lo, P.hi, P.f);
    for (int i = 0; i < ng; ++i) P.eg[i] = restrict_to(root.g[i], root.eg[i], P.lo, P.hi, P.g[i]);
    return search(S, root, P, ng, max_depth, budget, toi, static_cast<LongPass*>(nullptr));
  }
};

struct LongPass {
  const Setup<double>* S = nullptr;
  WidePass<long double> wide{kCcdPieceBudgetLong};
  // The third pass, in Quad, on the pieces the long-double one leaves undecided.
  WidePass<Quad> quad{kCcdPieceBudgetQuad};
  CcdCounters* counters = nullptr;
  // Exact touch at t = 1 (the input doubles): -1 not yet checked, 0 not proved, 1 proved.
  const CcdPoints* points = nullptr;
  const Piece<double>* root_d = nullptr;
  int ng_d = 0;
  int touch_at_end = -1;
  // The separation test has failed on all of [0, 1] (the fast path tried it).
  bool whole_not_separated = false;
  TouchCertificate* touch = nullptr;  ///< the query's certificate (nullptr: the search makes its own)
};

inline TouchCertificate& certificate_of(LongPass* lp, TouchCertificate& own) {
  return lp && lp->touch ? *lp->touch : own;
}

inline bool whole_not_separated(const LongPass& lp) { return lp.whole_not_separated; }

inline void count_touch(LongPass* lp) {
  if (lp && lp->counters) ++lp->counters->touches;
}

inline bool touches_at_end(LongPass& lp) {
  if (lp.touch_at_end < 0) {
    const bool maybe = may_touch_at(*lp.root_d, lp.ng_d, 1);
    lp.touch_at_end = maybe && (lp.S->kind == CcdKind::VertexFace ? exact_vertex_face_touch(lp.points->end)
                                                                  : exact_edge_edge_touch(lp.points->end));
  }
  return lp.touch_at_end == 1;
}

inline Outcome resolve_long(LongPass& lp, double lo, double hi, int depth, double& toi) {
  if (lp.counters) ++lp.counters->fallbacks;
  // Each pass that leaves the piece undecided stops at a start before which it cleared
  // everything in the piece: a time never later than the first contact.
  double undecided = lo;
  if constexpr (std::numeric_limits<long double>::digits > std::numeric_limits<double>::digits) {
    lp.wide.prepare(*lp.S);
    long double t = 0;
    const Outcome r = lp.wide.run(lo, hi, depth, kCcdMaxDepthLong, t);
    if (r == Outcome::Miss) return r;
    toi = round_down(t);
    if (r == Outcome::Hit) return r;
    undecided = toi;
  }
  // Still undecided: the whole piece again in Quad, whose error bounds are about 2^60 times
  // smaller than double's (a point passing 1e-17 from a segment's line is told apart).
  if (lp.quad.budget > 0) {
    lp.quad.prepare(*lp.S);
    Quad t = 0;
    // (pieces exact in Quad: 2^-100 in binary128, less where Quad is a narrower long double)
    constexpr int max_depth = std::min(kCcdMaxDepthQuad, kQuadDigits - 8);
    const Outcome r = lp.quad.run(lo, hi, depth, max_depth, t);
    if (r == Outcome::Miss) return r;
    toi = round_down(t);
    if (r == Outcome::Hit) return r;
    undecided = std::max(undecided, toi);
  }
  toi = undecided;
  return Outcome::Undecided;
}

}  // namespace mccd::detail
