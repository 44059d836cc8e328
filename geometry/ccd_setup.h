#pragma once
/// @file Internal: one elementary CCD query after loading. The points at t = 0 and t = 1 (scaled
/// exactly by a power of two), the difference vectors and the coplanarity cubic of stage (b),
/// the time pieces of stage (c), and the rigorous separation test along a direction that both
/// primitive kinds share.
#include <cfloat>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <mccd/geometry/ccd.h>
#include <mccd/geometry/ccd_bernstein.h>
#include <mccd/geometry/ccd_detail.h>

namespace mccd::detail {

// The query after loading: points at t = 0 (s) and t = 1 (e), scaled by a power of two so
// that the largest coordinate lies in [2^-60, 2^60]; `d` the scaled minimum distance.
template <class T>
struct Setup {
  using V = V3<T>;
  CcdKind kind;
  V s[4], e[4];
  T d = 0;
  T d_lo = 0;  // a lower bound of the scaled minimum distance (for proving "within d")
  V X00, X01, X10, X11;      // VF: B x C at (t0|t1) x (t0|t1); EE: da x db
  V A0, A1, B0, B1, C0, C1;  // VF: a-p, b-p, c-p; EE: da, db, w
  T alpha = 0, beta = 0, gamma = 0;
  Bern<3, T> f;
  T ef = 0;  // error bound of f
  T dN = 0;  // d * (bound on |n(t)| or |e(t)|)
  // Separation pairs x - y at t = 0 and 1 (VF: p - corner; EE: end of b - end of a).
  int npairs = 0;
  V D0[4], D1[4];
};

enum class Load { Ok, AllZero, Unsafe };

// Loads the points; `mx` is their largest absolute coordinate (from the box test of stage (a)).
inline Load load(const CcdPoints& p, double min_distance, Setup<double>& S, double mx) {
  // Both hold four points as 12 contiguous doubles: two block copies.
  static_assert(sizeof(S.s) == sizeof(p.start) && sizeof(S.e) == sizeof(p.end) && sizeof(p.start) == 12 * sizeof(double));
  std::memcpy(S.s, p.start.data(), sizeof(S.s));
  std::memcpy(S.e, p.end.data(), sizeof(S.e));
  S.d = S.d_lo = min_distance;
  if (mx <= 0x1p60 && mx >= 0x1p-60) return Load::Ok;
  if (mx == 0) return Load::AllZero;
  if (!std::isfinite(mx)) return Load::Unsafe;
  // Exact power-of-two scaling (every scaled coordinate stays a normal number or zero).
  const int ex = std::ilogb(mx);
  auto scale = [&](double& x) {
    x = std::ldexp(x, -ex);
    return x == 0 || std::fabs(x) >= DBL_MIN;
  };
  bool exact = true;
  for (int i = 0; i < 4; ++i)
    for (V3<double>* v : {&S.s[i], &S.e[i]}) exact = scale(v->x) && scale(v->y) && scale(v->z) && exact;
  if (!exact) return Load::Unsafe;
  if (min_distance > 0) {
    S.d = std::nextafter(std::ldexp(min_distance, -ex), HUGE_VAL);
    S.d_lo = std::nextafter(std::ldexp(min_distance, -ex), 0.0);
  }
  return Load::Ok;
}

/// The largest absolute coordinate of the eight points, NaN coordinates skipped (as a chain of
/// std::max(mx, |x|) from 0 skips them). SSE2: twelve pairs of coordinates, two at a time;
/// max_pd(x, m) keeps m when x is NaN, and the maximum of the others does not depend on order.
inline double max_abs_coordinate(const CcdPoints& p) {
  static_assert(sizeof(CcdPoints) == 24 * sizeof(double), "the eight points as 24 contiguous doubles");
  const double* x = p.start[0].data();
#if defined(__SSE2__)
  const __m128d magnitude = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
  __m128d m0 = _mm_setzero_pd(), m1 = _mm_setzero_pd();
  for (int i = 0; i < 24; i += 4) {
    m0 = _mm_max_pd(_mm_and_pd(_mm_loadu_pd(x + i), magnitude), m0);
    m1 = _mm_max_pd(_mm_and_pd(_mm_loadu_pd(x + i + 2), magnitude), m1);
  }
  const __m128d m = _mm_max_pd(m1, m0);
  const double a = _mm_cvtsd_f64(m), b = _mm_cvtsd_f64(_mm_unpackhi_pd(m, m));
  return std::max(a, b);
#else
  double mx = 0;
  for (int i = 0; i < 24; ++i) mx = std::max(mx, std::fabs(x[i]));
  return mx;
#endif
}

inline Load load(const CcdPoints& p, double min_distance, Setup<double>& S) {
  return load(p, min_distance, S, max_abs_coordinate(p));
}

// Inside functions g_i: necessary conditions for contact at a time t (all g_i(t) >= 0):
//   VF (with p the origin, A, B, C the corners): n = BxC + CxA + AxB, g = n.(BxC), n.(CxA),
//      n.(AxB); at a coplanar time these are u|n|^2, v|n|^2, w|n|^2 with (u, v, w) the
//      barycentric coordinates of p, so contact implies all >= 0, and all > 0 at a coplanar
//      time implies contact.
//   EE: e = da x db; g = (w x db).e, -((b0 - a1) x db).e, (w x da).e, (da x (b1 - a0)).e; if the
//      segments meet at a0 + s da = b0 + r db these are s|e|^2, (1-s)|e|^2, r|e|^2, (1-r)|e|^2.
// Pieces are dyadic intervals [lo, hi] of [0, 1], exact in T.
template <class T>
struct Piece {
  T lo, hi;
  int depth;
  Bern<3, T> f;
  T ef;
  Bern<4, T> g[4];
  T eg[4];
};

// The cubic and the inside functions at one instant (the fast path, geometry/ccd_fast.h),
// computed from the difference vectors interpolated to that instant. `ef` bounds the error of
// f (the same bound as the Bernstein coefficients of stage (b)); the inside functions' bounds
// come from magnitudes fixed per query (`inside_magnitudes` of each kind).
template <class T>
struct Snap {
  T f;
  T g[4];
  V3<T> N;  // VF: the face normal n; EE: e = da x db (the min_distance shortcut)
};

// Closest point to p on segment [a, b] (any point is fine for soundness).
template <class T>
inline V3<T> closest_on_segment(V3<T> p, V3<T> a, V3<T> b) {
  const V3<T> ab = b - a;
  const T den = dot(ab, ab);
  if (!(den > 0)) return a;
  const T t = std::clamp(dot(p - a, ab) / den, T(0), T(1));
  return a + ab * t;
}

template <class T>
inline T dist2(V3<T> a, V3<T> b) { return dot(a - b, a - b); }



// Separation over [lo, hi] along w: for every pair (x, y) of a corner x of the second and y
// of the first primitive (VF: x = p, y = corners; EE: x = ends of b, y = ends of a),
// w.(x(t) - y(t)) > d |w| (or, for every pair, < -d |w|). Each is linear in t:
// h(t) = (1-t) h0 + t h1 with h0, h1 computed to within 6 u |w|.|diff|; the bound at lo
// and hi is checked with a 4 u margin for the interpolation.
template <class T>
bool separated_along(const Setup<T>& S, V3<T> w, T lo, T hi) {
  using V = V3<T>;
  constexpr T u = unit_roundoff<T>();
  const T ww = dot(w, w);
  if (!(ww > 0) || !finite_(ww)) return false;
  const T margin = S.d > 0 ? S.d * sqrt_up(ww) * (1 + 8 * u) : T(0);
  bool pos = true, neg = true;
  for (int k = 0; k < S.npairs; ++k) {
    const V D0 = S.D0[k], D1 = S.D1[k];
    const T h0 = dot(w, D0), h1 = dot(w, D1);
    const T e0 = 6 * u * absdot(w, D0) + T(kTiny), e1 = 6 * u * absdot(w, D1) + T(kTiny);
    const T slack = 4 * u * (fabs_(h0) + fabs_(h1) + e0 + e1) + T(kTiny) + margin;
    if (pos) {
      const T l0 = h0 - e0, l1 = h1 - e1;
      pos = l0 + lo * (l1 - l0) > slack && l0 + hi * (l1 - l0) > slack;
    }
    if (neg) {
      const T u0 = h0 + e0, u1 = h1 + e1;
      neg = u0 + lo * (u1 - u0) < -slack && u0 + hi * (u1 - u0) < -slack;
    }
    if (!pos && !neg) return false;
  }
  return true;
}

}  // namespace mccd::detail
