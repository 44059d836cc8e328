#pragma once
/// @file Internal: the fast path of stage (c), tried first when min_distance = 0. It decides
/// the common cases with a handful of floating-point evaluations under rigorous error bounds
/// and leaves everything else (Unknown) to the certified search of geometry/ccd_search.h.
///
/// With d = 0, contact at time t needs f(t) = 0 and every inside function g_i(t) >= 0 (see
/// geometry/ccd_setup.h), and f(t) = 0 with every g_i(t) > 0 is a contact. The fast path:
///  1. isolates the roots of f on [0, 1] from Bernstein coefficients: by Descartes' rule of
///     signs in the Bernstein basis, the number of roots in an open piece (with multiplicity)
///     is at most the number V of sign changes of its coefficients, of the same parity. When
///     the end coefficients are certainly nonzero (beyond their error bound) with opposite
///     signs and no choice of the middle ones within their bounds can make V = 3, the piece
///     holds exactly one root, a simple one. Otherwise [0, 1] is split at estimates of the
///     cubic's critical points (any split is sound), each part restricted with rigorous
///     bounds (restrict_to) and either certainly nonzero or again a one-root piece; anything
///     else is Unknown;
///  2. for each root, earliest first: a floating-point estimate r (safeguarded Newton), and a
///     bracket [a, b] of grid points around it, of width 4 h, with h a power of two from the
///     slope at r and the error bound of f (h <= 2^-20). The cubic, evaluated at a and b from
///     the interpolated difference vectors (`snapshot`), must have certain signs (beyond
///     S.ef, or beyond the bound `f_error` local to that instant), those of the piece's ends:
///     then the root lies in (a, b), and f has no other root in the piece;
///  3. the inside functions at a and b (the same snapshots) enclose each g_i over [a, b]: for
///     t in [a, b], |g(t) - L(t)| <= (b - a)^2 / 8 max |g''| with L the chord through
///     g(a), g(b), and max |g''| on [0, 1] <= N (N - 1) 4 max |Bernstein coefficient| =
///     48 M_i for a quartic (M_i from `inside_magnitudes`); so with w = b - a every g_i lies
///     within 6 w^2 M_i below min(g(a), g(b)) and above max(g(a), g(b)). The snapshot's
///     rounding error is at most gamma_21 M_i < 21.01 u M_i (the kind headers count the
///     roundings). We test against E_i = M_i (24 u + 7 w^2) + 2 kTiny, computed in two
///     roundings, which covers both terms and the roundings of M_i (a few u) and of E_i.
///     Some g_i certainly negative over [a, b] (both values below -E_i): no contact at this
///     root, go on with the next one. Every g_i certainly positive: a certified contact at
///     the root, the first one (no earlier root had contact, and f vanishes nowhere else).
///     Otherwise Unknown;
///  4. toi of a certified contact, on the grid of G = 2^-32 as the search's: the grid point
///     at or below a, moved right by bisection over grid points inside (a, b) while f there
///     is certainly of the left sign (so still before the root). It ends with toi <= r <
///     toi + G, or with f within its error bound at toi + G (the contract's "numerically
///     zero" span); usually [a, b] lies in one grid cell and no extra evaluation is needed.
/// Every root rejected (or none at all): Miss. Nothing here reports a pair the search would
/// not (a certified contact is a true contact), so false positives can only go down.
///
/// The engine runs the simplest case (one sign change on [0, 1], no bisection for the time)
/// for several queries at once with the same operations in the same order
/// (LaneKernels::fast_tests, geometry/lane_masks_kernels.inl): a change of an operation or a
/// bound here is a change there (tests/geometry/test_lane_fast.cpp compares them).
#include <bit>
#include <cstdint>

#include <mccd/geometry/ccd_search.h>

namespace mccd::detail {

enum class Fast { Miss, Hit, Unknown };

// Halvings of the root isolation per query (each leaves one more part on the stack).
inline constexpr int kFastHalvings = 12;

// Exactly one root, simple, in the open piece whose Bernstein coefficients are `p` (each
// within e of the exact one): end coefficients of certain opposite signs, and no pattern
// + - + (or - + -) possible: with c0 > 0 > c3 that needs c1 >= 0 or c2 <= 0 for certain.
inline bool one_sign_change(const Bern<3, double>& p, double e) {
  const double c0 = p.c[0], c1 = p.c[1], c2 = p.c[2], c3 = p.c[3];
  if (c0 > e && c3 < -e) return c1 >= e || c2 <= -e;
  if (c0 < -e && c3 > e) return c1 <= -e || c2 >= e;
  return false;
}

// floor(x) for x in [0, 2^62] (a cast, where std::floor is a library call without SSE4.1).
inline double floor_nonneg(double x) { return static_cast<double>(static_cast<std::int64_t>(x)); }
inline double ceil_nonneg(double x) {
  const double f = floor_nonneg(x);
  return f < x ? f + 1 : f;
}

// Split points for the isolation: estimates of the critical points of the cubic (roots of the
// quadratic derivative) in (0, 1) on the grid of 2^-24, else 1/2. Only their position
// matters for success, never for soundness.
inline int split_points(const Bern<3, double>& f, double (&m)[2]) {
  const double d0 = f.c[1] - f.c[0], d1 = f.c[2] - f.c[1], d2 = f.c[3] - f.c[2];
  const double qa = d0 - 2 * d1 + d2, qb = 2 * (d1 - d0), qc = d0;  // qa t^2 + qb t + qc
  double r[2];
  int n = 0;
  if (qa == 0) {
    if (qb != 0) r[n++] = -qc / qb;
  } else {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc >= 0) {
      const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      r[n++] = q / qa;
      if (q != 0) r[n++] = qc / q;
    }
  }
  int k = 0;
  for (int i = 0; i < n; ++i) {
    const double x24 = r[i] * 0x1p24;
    if (!(x24 >= 1 && x24 <= 0x1p24 - 1)) continue;
    const double g = floor_nonneg(x24 + 0.5);
    const double x = g * 0x1p-24;
    if (k == 0 || x != m[0]) m[k++] = x;
  }
  if (k == 2 && m[0] > m[1]) std::swap(m[0], m[1]);
  if (k == 0) m[k++] = 0.5;
  return k;
}

// The smallest power of two >= x, for x in [2^-1000, 2^1000] (exponent bits, no libm call).
inline double pow2_at_least(double x) {
  const double p = std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) & 0x7ff0000000000000ull);
  return p == x ? p : 2 * p;
}

// Steps 2-4 on one piece [x, y] holding exactly one root of f, with sign `left_neg` to its
// left: Miss (no contact at that root), Hit (toi set) or Unknown.
template <class Kind>  // KindOps<K> of geometry/ccd_stages.h
Fast fast_root(const Setup<double>& S, const Bern<3, double>& p, double x, double y, const double (&M)[4],
               double& toi) {
  double slope = 0;
  const double r = root_estimate(p, x, y, slope);
  const bool left_neg = p.c[0] < 0;
  // Half-width so that |f| at a and b is about 4 times its error bound.
  const double hw = 4 * S.ef / std::fabs(slope);
  if (!(hw <= 0x1p-20)) return Fast::Unknown;
  const double h = hw < 0x1p-50 ? 0x1p-50 : pow2_at_least(hw);
  const double k = floor_nonneg(r / h);  // r in [x, y] within [0, 1], r / h <= 2^50
  const double a = std::max(x, (k - 2) * h), b = std::min(y, (k + 2) * h);
  Snap<double> sa, sb;
  Kind::snapshot(S, a, sa);
  Kind::snapshot(S, b, sb);
  // Certain signs: against S.ef, else against the bound local to the instant (f_error).
  auto certain = [&](double f, double t, bool neg) {
    return neg ? (f < -S.ef || f < -Kind::f_error(S, t)) : (f > S.ef || f > Kind::f_error(S, t));
  };
  if (!(certain(sa.f, a, left_neg) && certain(sb.f, b, !left_neg))) return Fast::Unknown;
  const double w = b - a;
  const double c = 24 * kU + 7 * (w * w);
  bool all_positive = true;
  for (int i = 0; i < Kind::inside_count; ++i) {
    const double e = M[i] * c + 2 * kTiny;
    if (sa.g[i] < -e && sb.g[i] < -e) return Fast::Miss;
    all_positive = all_positive && sa.g[i] > e && sb.g[i] > e;
  }
  if (!all_positive) return Fast::Unknown;
  // toi on the grid of G = 2^-32: lo <= r always; bisect on grid points strictly inside
  // (a, b) with certified signs of f until hi = lo + G, where hi >= b > r or f(hi) is not
  // certainly of the left sign (r < hi, or f within its error bound at hi).
  constexpr double G = 0x1p-32;
  double lo = floor_nonneg(a / G) * G, hi = ceil_nonneg(b / G) * G;
  while (hi - lo > G) {
    const double g = floor_nonneg((lo + hi) / (2 * G)) * G;
    bool left = g <= a;
    if (!left && g < b) {
      Snap<double> sg;
      Kind::snapshot(S, g, sg);
      left = certain(sg.f, g, left_neg);
    }
    (left ? lo : hi) = g;
  }
  toi = lo;
  return Fast::Hit;
}

// Step 1 and the loop over the roots: Miss, Hit (toi set) or Unknown. Parts of [0, 1] are
// taken earliest first from a stack; a part with more sign changes is halved (split_half,
// rigorous) while the budget lasts.
template <class Kind>
Fast fast_roots(const Setup<double>& S, double& toi) {
  if (!(std::fabs(S.f.c[0]) > S.ef && std::fabs(S.f.c[3]) > S.ef)) return Fast::Unknown;
  double M[4];
  Kind::inside_magnitudes(S, M);
  if (one_sign_change(S.f, S.ef)) return fast_root<Kind>(S, S.f, 0.0, 1.0, M, toi);
  struct Part {
    Bern<3, double> p;
    double e, lo, hi;
  };
  Part st[kFastHalvings + 3];
  int top = 0;
  double m[2];
  const int nm = split_points(S.f, m);
  if (nm == 1) {  // one de Casteljau step at the split point gives both parts
    st[0].lo = m[0], st[0].hi = 1, st[1].lo = 0, st[1].hi = m[0];
    st[0].e = st[1].e = split_at(S.f, S.ef, m[0], st[1].p, st[0].p);
    top = 2;
  } else {
    const double cut[4] = {0, m[0], m[1], 1};
    for (int i = 2; i >= 0; --i) {
      Part& P = st[top++];
      P.lo = cut[i], P.hi = cut[i + 1];
      P.e = restrict_to(S.f, S.ef, P.lo, P.hi, P.p);
    }
  }
  int halvings = kFastHalvings;
  while (top > 0) {
    const Part P = st[--top];
    if (definite_sign(P.p, P.e) != 0) continue;
    if (one_sign_change(P.p, P.e)) {
      const Fast r = fast_root<Kind>(S, P.p, P.lo, P.hi, M, toi);
      if (r != Fast::Miss) return r;
      continue;
    }
    if (--halvings < 0) return Fast::Unknown;
    Part& R = st[top++];
    Part& L = st[top++];
    L.e = R.e = split_half(P.p, P.e, L.p, R.p);
    L.lo = P.lo, L.hi = R.lo = (P.lo + P.hi) / 2, R.hi = P.hi;
  }
  return Fast::Miss;
}

// The fast path (d = 0) after stage (b): the roots of the cubic; where they cannot be
// isolated (the cubic within its error bound at t = 0 or t = 1, as for primitives that move
// in one plane), one try of the search's separation test over all of [0, 1].
template <class Kind>
Fast fast_decide(const Setup<double>& S, double& toi) {
  const Fast r = fast_roots<Kind>(S, toi);
  if (r == Fast::Unknown && separated(S, 0.0, 1.0)) return Fast::Miss;
  return r;
}

}  // namespace mccd::detail
