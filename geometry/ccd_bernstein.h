#pragma once
/// @file Internal: the arithmetic of the elementary CCD tests. Small 3-vectors over a scalar T
/// (double; long double or Quad in the wider passes), polynomials in Bernstein form over a time
/// piece, de Casteljau subdivision and restriction with rigorous forward error bounds.
///
/// Notation: u = 2^-53 (unit roundoff). Every floating-point operation on doubles rounds to
/// nearest, so a computed value of an expression made of +, -, * of exact inputs, with at
/// most k roundings along any path, differs from the exact value by at most gamma_k * M,
/// where M is the same expression evaluated on absolute values and gamma_k = k u / (1 - k u).
/// We bound M from the largest absolute coordinate of each difference vector, and add an
/// absolute term kTiny that covers underflow (coordinates are kept in [2^-60, 2^60] by an
/// exact power-of-two scaling, so no product can overflow and underflow errors are far
/// below kTiny).
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace mccd::detail {

constexpr double kU = 0x1p-53;
constexpr double kTiny = 0x1p-800;
// Unit roundoff of the scalar type T of stage (c) (double; long double in the second pass;
// Quad in the third).
template <class T>
constexpr T unit_roundoff() { return std::numeric_limits<T>::epsilon() / 2; }

/// The scalar of stage (c)'s third pass, for the few pieces the double and long-double passes
/// leave undecided: IEEE binary128 (113-bit significand) as GCC's and clang's __float128
/// (software arithmetic) where they have it (x86-64); elsewhere long double (binary128 on
/// AArch64 Linux; where it is narrower the third pass only repeats the second, within its
/// exact depth). Strict C++20 has no functions for __float128: the few stage (c) needs are
/// below, for every scalar type.
/// kSoftQuad<T>: whether T is __float128, whose functions are written here.
#if defined(__SIZEOF_FLOAT128__)
using Quad = __float128;
inline constexpr int kQuadDigits = 113;
template <class T>
inline constexpr bool kSoftQuad = std::is_same_v<T, Quad>;
template <>
constexpr Quad unit_roundoff<Quad>() { return Quad(0x1p-113); }
#else
using Quad = long double;
inline constexpr int kQuadDigits = std::numeric_limits<long double>::digits;
template <class T>
inline constexpr bool kSoftQuad = false;
#endif

template <class T>
inline T fabs_(T x) {
  if constexpr (kSoftQuad<T>)
    return x < 0 ? -x : x;
  else
    return std::fabs(x);
}
// 2^e, exact for |e| <= 1000.
template <class T>
inline T pow2(int e) { return T(std::ldexp(1.0, e)); }
// The largest integer <= x (__float128: for |x| < 2^112, where adding and taking 2^112 away
// rounds x to an integer exactly; beyond it every value is an integer).
template <class T>
inline T floor_(T x) {
  if constexpr (kSoftQuad<T>) {
    const T big = pow2<T>(112);
    if (!(fabs_(x) < big)) return x;
    T y = x >= 0 ? (x + big) - big : (x - big) + big;
    return y > x ? y - 1 : y;
  } else {
    return std::floor(x);
  }
}
template <class T>
inline bool finite_(T x) { return x - x == 0; }
// At least sqrt(x) (__float128: through long double, rounded to nearest within 2^-64 on
// x86-64, then raised by 2^-60); x finite and >= 0.
template <class T>
inline T sqrt_up(T x) {
  if constexpr (kSoftQuad<T>) {
    static_assert(std::numeric_limits<long double>::digits >= 64);
    return T(std::sqrt(static_cast<long double>(x))) * (T(1) + pow2<T>(-60));
  } else {
    return std::sqrt(x);
  }
}

template <class T>
struct V3 {
  T x, y, z;
};
template <class T>
inline V3<T> operator-(V3<T> a, V3<T> b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T>
inline V3<T> operator+(V3<T> a, V3<T> b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T>
inline V3<T> operator*(V3<T> a, T s) { return {a.x * s, a.y * s, a.z * s}; }
template <class T>
inline V3<T> cross(V3<T> a, V3<T> b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
template <class T>
inline T dot(V3<T> a, V3<T> b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T>
inline T absdot(V3<T> a, V3<T> b) {
  return fabs_(a.x) * fabs_(b.x) + fabs_(a.y) * fabs_(b.y) + fabs_(a.z) * fabs_(b.z);
}
template <class T>
inline T amax(V3<T> a) { return std::max(fabs_(a.x), std::max(fabs_(a.y), fabs_(a.z))); }
template <class T>
inline V3<T> lerp(V3<T> a, V3<T> b, T t) { return a + (b - a) * t; }
template <class T>
inline V3<T> vabs(V3<T> a) { return {fabs_(a.x), fabs_(a.y), fabs_(a.z)}; }
// The magnitude expression of a cross product: the same products, all added.
template <class T>
inline V3<T> across(V3<T> a, V3<T> b) { return {a.y * b.z + a.z * b.y, a.z * b.x + a.x * b.z, a.x * b.y + a.y * b.x}; }

// A polynomial of degree N in Bernstein form over the current time piece.
template <int N, class T = double>
struct Bern {
  T c[N + 1];
};

template <int N, class T>
inline T maxabs(const Bern<N, T>& p) {
  T m = 0;
  for (int k = 0; k <= N; ++k) m = std::max(m, fabs_(p.c[k]));
  return m;
}

// +1: every coefficient > thr (the polynomial is > 0 on the piece); -1: every one < -thr;
// 0: undecided. NaN never decides.
template <int N, class T>
inline int definite_sign(const Bern<N, T>& p, T thr) {
  bool pos = true, neg = true;
  for (int k = 0; k <= N; ++k) {
    pos = pos && p.c[k] > thr;
    neg = neg && p.c[k] < -thr;
  }
  return pos ? 1 : (neg ? -1 : 0);
}

// de Casteljau at 1/2. Each average (x + y) * 0.5 rounds once (the halving is exact, barring
// underflow, covered by kTiny); N levels, every intermediate bounded by max |c|, so the
// error bound grows by N u max|c| (taken twice to cover the rounding of the bound itself).
template <int N, class T>
inline T split_half(const Bern<N, T>& p, T err, Bern<N, T>& l, Bern<N, T>& r) {
  T t[N + 1];
  for (int k = 0; k <= N; ++k) t[k] = p.c[k];
  l.c[0] = t[0];
  r.c[N] = t[N];
  for (int k = 1; k <= N; ++k) {
    for (int i = 0; i <= N - k; ++i) t[i] = (t[i] + t[i + 1]) * 0.5;
    l.c[k] = t[0];
    r.c[N - k] = t[N - k];
  }
  return err + 2 * N * unit_roundoff<T>() * maxabs(p) + T(kTiny);
}

// de Casteljau at s (0 < s < 1, 1 - s exact): the polynomial on the piece's [0, s] (l) and
// [s, 1] (r), each over its own [0, 1]. Every lerp (1 - s) x + s y is a convex combination that
// rounds three times, within 2.01 u max |c|; N levels: the error bound grows by 4 N u max|c|
// (as for restrict_to), exact errors propagating with weight at most 1.
template <int N, class T>
inline T split_at(const Bern<N, T>& p, T err, T s, Bern<N, T>& l, Bern<N, T>& r) {
  const T s1 = 1 - s;
  T t[N + 1];
  for (int k = 0; k <= N; ++k) t[k] = p.c[k];
  l.c[0] = t[0];
  r.c[N] = t[N];
  for (int k = 1; k <= N; ++k) {
    for (int i = 0; i <= N - k; ++i) t[i] = s1 * t[i] + s * t[i + 1];
    l.c[k] = t[0];
    r.c[N - k] = t[N - k];
  }
  return err + 4 * N * unit_roundoff<T>() * maxabs(p) + T(kTiny);
}

// Quadratic vector b0 (1-t)^2 + 2 b1 t (1-t) + b2 t^2 = a(t) x b(t) for linear a, b.
// The same polynomial in Bernstein form over [lo, hi] (dyadic, so 1 - lo and 1 - hi are
// exact): coefficient k is the blossom at (lo, ..., lo, hi, ..., hi) with k copies of hi.
// Every lerp (1-t) a + t b rounds at most twice and stays within max |c|, so the error
// grows by at most 2 N u max|c| (taken as 4 N u).
template <int N, class T>
inline T restrict_to(const Bern<N, T>& p, T err, T lo, T hi, Bern<N, T>& out) {
  T row[N + 1];
  for (int k = 0; k <= N; ++k) row[k] = p.c[k];
  const T l1 = 1 - lo, h1 = 1 - hi;
  for (int j = 0; j <= N; ++j) {
    T tmp[N + 1];
    // (the whole row: a copy of fixed length stays in registers, a shorter one became a call)
    for (int i = 0; i <= N; ++i) tmp[i] = row[i];
    for (int level = 0; level < N - j; ++level)
      for (int i = 0; i < N - j - level; ++i) tmp[i] = l1 * tmp[i] + lo * tmp[i + 1];
    out.c[j] = tmp[0];
    for (int i = 0; i < N - j; ++i) row[i] = h1 * row[i] + hi * row[i + 1];
  }
  return err + 4 * N * unit_roundoff<T>() * maxabs(p) + T(kTiny);
}

template <class T>
struct QuadV {
  V3<T> q[3];
};
template <class T>
inline QuadV<T> quad_cross(V3<T> a0, V3<T> a1, V3<T> b0, V3<T> b1) {
  return {{cross(a0, b0), (cross(a0, b1) + cross(a1, b0)) * T(0.5), cross(a1, b1)}};
}
// Quartic n(t) . m(t) for quadratic vectors n, m.
template <class T>
inline Bern<4, T> quartic(const QuadV<T>& n, const QuadV<T>& m) {
  Bern<4, T> g;
  g.c[0] = dot(n.q[0], m.q[0]);
  g.c[1] = (dot(n.q[0], m.q[1]) + dot(n.q[1], m.q[0])) * T(0.5);
  g.c[2] = (dot(n.q[0], m.q[2]) + T(4) * dot(n.q[1], m.q[1]) + dot(n.q[2], m.q[0])) / T(6);
  g.c[3] = (dot(n.q[1], m.q[2]) + dot(n.q[2], m.q[1])) * T(0.5);
  g.c[4] = dot(n.q[2], m.q[2]);
  return g;
}
// Cubic a(t) . q(t) for linear a and quadratic q = (q0, q1, q2); `q1x2` = 2 q1.
template <class T>
inline Bern<3, T> cubic(V3<T> a0, V3<T> a1, V3<T> q0, V3<T> q1x2, V3<T> q2) {
  Bern<3, T> f;
  f.c[0] = dot(a0, q0);
  f.c[1] = (dot(a0, q1x2) + dot(a1, q0)) / T(3);
  f.c[2] = (dot(a0, q2) + dot(a1, q1x2)) / T(3);
  f.c[3] = dot(a1, q2);
  return f;
}

template <class T>
inline QuadV<T> quad_across(V3<T> a0, V3<T> a1, V3<T> b0, V3<T> b1) {
  a0 = vabs(a0), a1 = vabs(a1), b0 = vabs(b0), b1 = vabs(b1);
  return {{across(a0, b0), (across(a0, b1) + across(a1, b0)) * T(0.5), across(a1, b1)}};
}
template <int N, class T>
inline T error_bound(const Bern<N, T>& magnitude, int k) {
  return T(k) * unit_roundoff<T>() * maxabs(magnitude) + T(kTiny);
}

// The cubic (Bernstein form over a piece) at s in [0, 1] of the piece, by de Casteljau.
template <class T>
inline T eval_at(const Bern<3, T>& f, T s) {
  T b[4] = {f.c[0], f.c[1], f.c[2], f.c[3]};
  for (int k = 3; k > 0; --k)
    for (int i = 0; i < k; ++i) b[i] = b[i] + s * (b[i + 1] - b[i]);
  return b[0];
}

// Floating-point estimate of the only root of the cubic p (Bernstein form over [x, y], end
// values of opposite signs): safeguarded Newton in s in [0, 1] on de Casteljau values, to
// about 2^-40 of the piece. Returns the time, and the slope df/dt there in `slope`. Only an
// estimate: callers place a bracket or window with it and then check that rigorously (the
// fast path, geometry/ccd_fast.h; the search's jump to the root, geometry/ccd_search.h).
template <class T>
inline T root_estimate(const Bern<3, T>& p, std::type_identity_t<T> x, std::type_identity_t<T> y, T& slope) {
  const bool neg0 = p.c[0] < 0;
  T sl = 0, sr = 1;
  // Start where the control polygon first leaves the sign of c0 (it converges to the curve
  // quadratically under subdivision, so this is already close).
  T s = 0.5;
  for (int k = 0; k < 3; ++k)
    if ((p.c[k + 1] < 0) != neg0) {
      const T q = (k + p.c[k] / (p.c[k] - p.c[k + 1])) / 3;
      if (q > 0 && q < 1) s = q;
      break;
    }
  T d = 0;
  for (int it = 0; it < 40; ++it) {
    T b[3] = {p.c[0] + s * (p.c[1] - p.c[0]), p.c[1] + s * (p.c[2] - p.c[1]), p.c[2] + s * (p.c[3] - p.c[2])};
    b[0] += s * (b[1] - b[0]);
    b[1] += s * (b[2] - b[1]);
    const T v = b[0] + s * (b[1] - b[0]);
    d = 3 * (b[1] - b[0]);
    if (v == 0) break;
    (((v < 0) == neg0) ? sl : sr) = s;
    const T step = v / d;
    const T ns = s - step;
    // A step this small is converged (the next one would be about step^2 times a modest
    // factor); near the root it may not even move s, so test it before the bracket.
    if (fabs_(step) <= (kSoftQuad<T> ? T(0x1p-90) : T(0x1p-40))) {
      s = std::clamp(ns, sl, sr);
      break;
    }
    s = ns > sl && ns < sr ? ns : 0.5 * (sl + sr);
    if (sr - sl <= (kSoftQuad<T> ? T(0x1p-105) : T(0x1p-52))) break;
  }
  slope = d / (y - x);
  return x + s * (y - x);
}

}  // namespace mccd::detail
