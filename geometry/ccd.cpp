// Elementary CCD tests (vertex-face, edge-edge) under linear motion; see ccd.h for the
// contract and the error analysis in the comments below.
//
// Notation: u = 2^-53 (unit roundoff). Every floating-point operation on doubles rounds to
// nearest, so a computed value of an expression made of +, -, * of exact inputs, with at
// most k roundings along any path, differs from the exact value by at most gamma_k * M,
// where M is the same expression evaluated on absolute values and gamma_k = k u / (1 - k u).
// We bound M from the largest absolute coordinate of each difference vector, and add an
// absolute term kTiny that covers underflow (coordinates are kept in [2^-60, 2^60] by an
// exact power-of-two scaling, so no product can overflow and underflow errors are far
// below kTiny).
#include "geometry/ccd.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <type_traits>

#include "geometry/ccd_detail.h"
#include "geometry/ccd_exact.h"

namespace mccd {
namespace detail {
namespace {

constexpr double kU = 0x1p-53;
constexpr double kTiny = 0x1p-800;
// Unit roundoff of the scalar type T of stage (c) (double, or long double in the second pass).
template <class T>
constexpr T unit_roundoff() { return std::numeric_limits<T>::epsilon() / 2; }
// Cheap error bound of the coplanarity cubic (stage b): at most 9 roundings, magnitude
// <= 6 alpha beta gamma; gamma_9 * 6 < 60 u, taken as 96 u.
constexpr double kCubicErr = 96 * kU;

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
  return std::fabs(a.x) * std::fabs(b.x) + std::fabs(a.y) * std::fabs(b.y) + std::fabs(a.z) * std::fabs(b.z);
}
template <class T>
inline T amax(V3<T> a) { return std::max(std::fabs(a.x), std::max(std::fabs(a.y), std::fabs(a.z))); }
template <class T>
inline V3<T> lerp(V3<T> a, V3<T> b, T t) { return a + (b - a) * t; }
template <class T>
inline V3<T> vabs(V3<T> a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
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
  for (int k = 0; k <= N; ++k) m = std::max(m, std::fabs(p.c[k]));
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
    for (int i = 0; i <= N - j; ++i) tmp[i] = row[i];
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

// The query after loading: points at t = 0 (s) and t = 1 (e), scaled by a power of two so
// that the largest coordinate lies in [2^-60, 2^60]; `d` the scaled minimum distance.
template <class T>
struct Setup {
  using V = V3<T>;
  CcdKind kind;
  V s[4], e[4];
  T d = 0;
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

Load load(const CcdPoints& p, double min_distance, Setup<double>& S) {
  double mx = 0;
  for (int i = 0; i < 4; ++i) {
    S.s[i] = {p.start[i].x(), p.start[i].y(), p.start[i].z()};
    S.e[i] = {p.end[i].x(), p.end[i].y(), p.end[i].z()};
    mx = std::max(mx, std::max(amax(S.s[i]), amax(S.e[i])));
  }
  S.d = min_distance;
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
  if (min_distance > 0) S.d = std::nextafter(std::ldexp(min_distance, -ex), HUGE_VAL);
  return Load::Ok;
}

// Stage (b): the coplanarity cubic in Bernstein form with its error bound.
//   VF: f(t) = det(a - p, b - p, c - p) (A, B, C), zero iff the four points are coplanar.
//   EE: f(t) = det(da, db, w), da = a1 - a0, db = b1 - b0, w = b0 - a0.
// Error: 6 products of three differences per determinant, at most 9 roundings: |err| <=
// gamma_9 * 6 alpha beta gamma < 96 u alpha beta gamma (alpha, beta, gamma: largest
// absolute coordinate of the three difference vectors at t = 0 and 1).
template <class T>
void coplanarity(Setup<T>& S) {
  constexpr T u = unit_roundoff<T>();
  if (S.kind == CcdKind::VertexFace) {
    S.A0 = S.s[1] - S.s[0], S.A1 = S.e[1] - S.e[0];
    S.B0 = S.s[2] - S.s[0], S.B1 = S.e[2] - S.e[0];
    S.C0 = S.s[3] - S.s[0], S.C1 = S.e[3] - S.e[0];
    S.X00 = cross(S.B0, S.C0), S.X01 = cross(S.B0, S.C1), S.X10 = cross(S.B1, S.C0), S.X11 = cross(S.B1, S.C1);
  } else {
    S.A0 = S.s[1] - S.s[0], S.A1 = S.e[1] - S.e[0];  // da
    S.B0 = S.s[3] - S.s[2], S.B1 = S.e[3] - S.e[2];  // db
    S.C0 = S.s[2] - S.s[0], S.C1 = S.e[2] - S.e[0];  // w
    S.X00 = cross(S.A0, S.B0), S.X01 = cross(S.A0, S.B1), S.X10 = cross(S.A1, S.B0), S.X11 = cross(S.A1, S.B1);
  }
  if (S.kind == CcdKind::VertexFace) {
    S.npairs = 3;
    for (int j = 0; j < 3; ++j) S.D0[j] = S.s[0] - S.s[j + 1], S.D1[j] = S.e[0] - S.e[j + 1];
  } else {
    S.npairs = 4;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        S.D0[2 * j + i] = S.s[2 + j] - S.s[i], S.D1[2 * j + i] = S.e[2 + j] - S.e[i];
  }
  S.alpha = std::max(amax(S.A0), amax(S.A1));
  S.beta = std::max(amax(S.B0), amax(S.B1));
  S.gamma = std::max(amax(S.C0), amax(S.C1));
  const V3<T> a0 = S.kind == CcdKind::VertexFace ? S.A0 : S.C0;
  const V3<T> a1 = S.kind == CcdKind::VertexFace ? S.A1 : S.C1;
  S.f = cubic(a0, a1, S.X00, S.X01 + S.X10, S.X11);
  S.ef = T(96) * u * (S.alpha * S.beta * S.gamma) + T(kTiny);
  S.dN = 0;
  if (S.d > 0) {
    // |n(t)| <= |BxC| + |CxA| + |AxB| <= 3 (bg + ga + ab) (VF); |e(t)| <= 3 ab (EE).
    const T nmax = S.kind == CcdKind::VertexFace ? 3 * (S.beta * S.gamma + S.gamma * S.alpha + S.alpha * S.beta)
                                                 : 3 * S.alpha * S.beta;
    S.dN = S.d * nmax * (1 + 16 * u);
  }
}

// ---- Stage (c): time pieces -------------------------------------------------------------

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

template <class T>
inline QuadV<T> quad_across(V3<T> a0, V3<T> a1, V3<T> b0, V3<T> b1) {
  a0 = vabs(a0), a1 = vabs(a1), b0 = vabs(b0), b1 = vabs(b1);
  return {{across(a0, b0), (across(a0, b1) + across(a1, b0)) * T(0.5), across(a1, b1)}};
}
template <int N, class T>
inline T error_bound(const Bern<N, T>& magnitude, int k) {
  return T(k) * unit_roundoff<T>() * maxabs(magnitude) + T(kTiny);
}

// Computes the inside functions on [0, 1] and, for every polynomial of stage (c) (the cubic
// included), an error bound from its magnitude expression: gamma_k times the same expression
// on absolute values (k roundings at most: 9 for the cubic, 12 for the quartics; we take
// 16 u and 20 u, which also covers the rounding of the magnitudes themselves).
template <class T>
int setup_inside(const Setup<T>& S, Piece<T>& P) {
  using V = V3<T>;
  QuadV<T> aX;
  int ng;
  if (S.kind == CcdKind::VertexFace) {
    const QuadV<T> X{{S.X00, (S.X01 + S.X10) * T(0.5), S.X11}};
    const QuadV<T> Y = quad_cross(S.C0, S.C1, S.A0, S.A1);
    const QuadV<T> Z = quad_cross(S.A0, S.A1, S.B0, S.B1);
    aX = quad_across(S.B0, S.B1, S.C0, S.C1);
    const QuadV<T> aY = quad_across(S.C0, S.C1, S.A0, S.A1);
    const QuadV<T> aZ = quad_across(S.A0, S.A1, S.B0, S.B1);
    QuadV<T> n, an;
    for (int k = 0; k < 3; ++k) n.q[k] = X.q[k] + Y.q[k] + Z.q[k], an.q[k] = aX.q[k] + aY.q[k] + aZ.q[k];
    P.g[0] = quartic(n, X);
    P.g[1] = quartic(n, Y);
    P.g[2] = quartic(n, Z);
    P.eg[0] = error_bound(quartic(an, aX), 20);
    P.eg[1] = error_bound(quartic(an, aY), 20);
    P.eg[2] = error_bound(quartic(an, aZ), 20);
    ng = 3;
  } else {
    const V da0 = S.A0, da1 = S.A1, db0 = S.B0, db1 = S.B1, w0 = S.C0, w1 = S.C1;
    const V v0 = S.s[2] - S.s[1], v1 = S.e[2] - S.e[1];  // b0 - a1
    const V z0 = S.s[3] - S.s[0], z1 = S.e[3] - S.e[0];  // b1 - a0
    const QuadV<T> e{{S.X00, (S.X01 + S.X10) * T(0.5), S.X11}};
    aX = quad_across(da0, da1, db0, db1);
    P.g[0] = quartic(e, quad_cross(w0, w1, db0, db1));
    P.g[1] = quartic(e, quad_cross(v0, v1, db0, db1));
    for (T& c : P.g[1].c) c = -c;
    P.g[2] = quartic(e, quad_cross(w0, w1, da0, da1));
    P.g[3] = quartic(e, quad_cross(da0, da1, z0, z1));
    P.eg[0] = error_bound(quartic(aX, quad_across(w0, w1, db0, db1)), 20);
    P.eg[1] = error_bound(quartic(aX, quad_across(v0, v1, db0, db1)), 20);
    P.eg[2] = error_bound(quartic(aX, quad_across(w0, w1, da0, da1)), 20);
    P.eg[3] = error_bound(quartic(aX, quad_across(da0, da1, z0, z1)), 20);
    ng = 4;
  }
  // The cubic: a(t) . X(t) with a = A (VF) or w (EE).
  const V a0 = vabs(S.kind == CcdKind::VertexFace ? S.A0 : S.C0);
  const V a1 = vabs(S.kind == CcdKind::VertexFace ? S.A1 : S.C1);
  P.ef = std::min(S.ef, error_bound(cubic(a0, a1, aX.q[0], aX.q[1] * T(2), aX.q[2]), 16));
  return ng;
}

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

// A separating direction at time t: from the closest point of the face / edge a to p / edge b.
template <class T>
V3<T> separating_direction(const Setup<T>& S, T t) {
  using V = V3<T>;
  V P[4];
  for (int i = 0; i < 4; ++i) P[i] = lerp(S.s[i], S.e[i], t);
  if (S.kind == CcdKind::VertexFace) {
    const V p = P[0], a = P[1], b = P[2], c = P[3];
    V best = closest_on_segment(p, a, b);
    T bd = dist2(p, best);
    for (V q : {closest_on_segment(p, b, c), closest_on_segment(p, c, a)}) {
      const T dq = dist2(p, q);
      if (dq < bd) bd = dq, best = q;
    }
    const V n = cross(b - a, c - a);
    const T nn = dot(n, n);
    if (nn > 0) {
      const V q = p - n * (dot(p - a, n) / nn);
      if (dot(n, cross(b - q, c - q)) >= 0 && dot(n, cross(c - q, a - q)) >= 0 && dot(n, cross(a - q, b - q)) >= 0 &&
          dist2(p, q) < bd)
        best = q;
    }
    return p - best;
  }
  // Closest points of segments [a0, a1] and [b0, b1] (clamped; degenerate cases tolerated).
  const V a0 = P[0], a1 = P[1], b0 = P[2], b1 = P[3];
  const V d1 = a1 - a0, d2 = b1 - b0, r = a0 - b0;
  const T A = dot(d1, d1), E = dot(d2, d2), F = dot(d2, r);
  T s = 0, w = 0;
  if (!(A > 0) && !(E > 0)) {
    s = w = 0;
  } else if (!(A > 0)) {
    w = std::clamp(F / E, T(0), T(1));
  } else {
    const T c = dot(d1, r);
    if (!(E > 0)) {
      s = std::clamp(-c / A, T(0), T(1));
    } else {
      const T b = dot(d1, d2), den = A * E - b * b;
      s = den > 0 ? std::clamp((b * F - c * E) / den, T(0), T(1)) : T(0);
      w = (b * s + F) / E;
      if (w < 0) {
        w = 0, s = std::clamp(-c / A, T(0), T(1));
      } else if (w > 1) {
        w = 1, s = std::clamp((b - c) / A, T(0), T(1));
      }
    }
  }
  return (b0 + d2 * w) - (a0 + d1 * s);
}

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
  if (!(ww > 0) || !std::isfinite(ww)) return false;
  const T margin = S.d > 0 ? S.d * std::sqrt(ww) * (1 + 8 * u) : T(0);
  bool pos = true, neg = true;
  for (int k = 0; k < S.npairs; ++k) {
    const V D0 = S.D0[k], D1 = S.D1[k];
    const T h0 = dot(w, D0), h1 = dot(w, D1);
    const T e0 = 6 * u * absdot(w, D0) + T(kTiny), e1 = 6 * u * absdot(w, D1) + T(kTiny);
    const T slack = 4 * u * (std::fabs(h0) + std::fabs(h1) + e0 + e1) + T(kTiny) + margin;
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

// Candidate separating directions at the middle of the piece: the closest-point direction,
// then the separating axes of the two convex primitives (VF: the face normal and its three
// in-plane edge normals; EE: da x db and its in-plane normals to each edge). Any direction
// is sound: the test itself is rigorous; good directions only make it succeed sooner.
template <class T>
bool separated(const Setup<T>& S, T lo, T hi) {
  using V = V3<T>;
  const T t = (lo + hi) / 2;
  if (separated_along(S, separating_direction(S, t), lo, hi)) return true;
  // Relative coordinates (origin at point 0) keep the rounding of the axes relative to u.
  V R[4];
  for (int i = 0; i < 4; ++i) R[i] = lerp(S.s[i] - S.s[0], S.e[i] - S.e[0], t);
  if (S.kind == CcdKind::VertexFace) {
    const V ab = R[2] - R[1], bc = R[3] - R[2], ca = R[1] - R[3];
    const V n = cross(ab, R[3] - R[1]);
    return separated_along(S, n, lo, hi) || separated_along(S, cross(n, ab), lo, hi) ||
           separated_along(S, cross(n, bc), lo, hi) || separated_along(S, cross(n, ca), lo, hi);
  }
  const V da = R[1], db = R[3] - R[2];
  const V e = cross(da, db);
  return separated_along(S, e, lo, hi) || separated_along(S, cross(e, da), lo, hi) ||
         separated_along(S, cross(e, db), lo, hi);
}

// The earliest point of [lo, hi] where the cubic may vanish, given that it certainly does
// vanish in [lo, hi] (opposite certain signs at the ends): bisect, keeping the left half
// unless the cubic is certainly nonzero on it.
template <class T>
T refine_toi(Bern<3, T> f, T ef, T lo, T hi, int depth, int max_depth) {
  while (depth < max_depth) {
    Bern<3, T> l, r;
    const T e = split_half(f, ef, l, r);
    const T mid = (lo + hi) / 2;
    if (definite_sign(l, e) != 0) {
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
  Item st[kCcdMaxDepthLong + 4];
  int top = 0;
  st[top++] = {P.f, P.ef, P.lo, P.hi, P.depth};
  while (top > 0) {
    const Item I = st[--top];
    if (definite_sign(I.f, I.ef + dN) != 0) continue;
    const T c0 = I.f.c[0], c3 = I.f.c[3];
    if ((c0 > I.ef && c3 < -I.ef) || (c0 < -I.ef && c3 > I.ef)) {
      // With d > 0 the first time within d may precede the coplanar time: keep lo.
      toi = dN > 0 ? I.lo : refine_toi(I.f, I.ef, I.lo, I.hi, I.depth, kCcdToiDepth);
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

// The cubic (Bernstein form over a piece) at s in [0, 1] of the piece, by de Casteljau.
template <class T>
inline T eval_at(const Bern<3, T>& f, T s) {
  T b[4] = {f.c[0], f.c[1], f.c[2], f.c[3]};
  for (int k = 3; k > 0; --k)
    for (int i = 0; i < k; ++i) b[i] = b[i] + s * (b[i + 1] - b[i]);
  return b[0];
}

// Shortcut of the bisection on a piece P where the cubic certainly changes sign and nothing
// else is decided: locate the sign change (floating-point bisection on f; any estimate is
// sound), take the window W of width 16 h (h = 2^-max_depth, W on the grid of h, so every
// bound used below is exact in T and 1 - lo, 1 - hi are exact) around it, and prove with
// rigorous bounds (the polynomials restricted from the root piece) that the cubic is
// certainly nonzero (beyond d |n|) on P left and right of W: no contact there. Then W, with
// every polynomial restricted to it, replaces P; it lies where P would have been bisected
// to after about max_depth - 4 levels. False (nothing changed) when the proof fails.
template <class T>
bool jump_to_root(const Piece<T>& R, const Piece<T>& P, int ng, T dN, int max_depth, Piece<T>& W) {
  const T c0 = P.f.c[0], c3 = P.f.c[3];
  if (!((c0 > P.ef && c3 < -P.ef) || (c0 < -P.ef && c3 > P.ef))) return false;
  const T h = std::ldexp(T(1), -max_depth);
  const T width = P.hi - P.lo;
  if (width <= std::ldexp(T(1), 6 - max_depth)) return false;
  const bool neg0 = c0 < 0;
  T sl = 0, sr = 1;
  for (int it = 0; it < 100 && (sr - sl) * width > h; ++it) {
    const T sm = (sl + sr) / 2;
    if ((eval_at(P.f, sm) < 0) == neg0)
      sl = sm;
    else
      sr = sm;
  }
  const T ts = P.lo + (sl + sr) / 2 * width;
  // Window half-widths 8 h, 256 h, 8192 h: the uncertainty of the sign change may be wider
  // than a few h when the error bounds are large against the slope of the cubic.
  T a = 0, b = 0;
  int k = 3;
  for (; k <= 13; k += 5) {
    const T m = std::ldexp(T(1), k);
    a = std::max(P.lo, std::floor(ts / h - m) * h);
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

struct LongPass;
Outcome resolve_long(LongPass& lp, double lo, double hi, int depth, double& toi);
bool touches_at_end(LongPass& lp);

template <class T>
Outcome search(const Setup<T>& S, const Piece<T>& root, const Piece<T>& start, int ng, int max_depth, int& budget,
               T& toi, LongPass* long_pass) {
  Piece<T> stack[kCcdMaxDepthLong + 4];
  int top = 0;
  stack[top++] = start;
  const bool use_inside = !(S.d > 0);
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
    // The separation test is the most expensive one: tried at every third level only.
    if ((P.depth % 3 == 0 || P.depth >= max_depth - 1) && separated(S, P.lo, P.hi)) continue;
    if constexpr (std::is_same_v<T, double>) {
      // Every earlier piece is cleared; with a proved touch at t = 1, the first contact lies
      // in [lo, 1]: report it at lo instead of bisecting further.
      if (P.depth >= kCcdCertDepth && long_pass && touches_at_end(*long_pass)) {
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
inline double round_down(long double x) {
  double r = static_cast<double>(x);
  if (static_cast<long double>(r) > x) r = std::nextafter(r, -HUGE_VAL);
  return r;
}

// The extended-precision pass (where long double is wider than double): the same search,
// with error bounds about 2^11 times smaller, on the pieces the double search left
// undecided at its maximum depth. Its setup is built on first use.
struct LongPass {
  const Setup<double>* S = nullptr;
  bool ready = false;
  Setup<long double> L;
  Piece<long double> root;
  int ng = 0;
  int budget = kCcdPieceBudgetLong;
  CcdCounters* counters = nullptr;
  // Exact touch at t = 1 (the input doubles): -1 not yet checked, 0 not proved, 1 proved.
  const CcdPoints* points = nullptr;
  const Piece<double>* root_d = nullptr;
  int ng_d = 0;
  int touch_at_end = -1;
};

bool touches_at_end(LongPass& lp) {
  if (lp.touch_at_end < 0) {
    const bool maybe = may_touch_at(*lp.root_d, lp.ng_d, 1);
    lp.touch_at_end = maybe && (lp.S->kind == CcdKind::VertexFace ? exact_vertex_face_touch(lp.points->end)
                                                                  : exact_edge_edge_touch(lp.points->end));
  }
  return lp.touch_at_end == 1;
}

Outcome resolve_long(LongPass& lp, double lo, double hi, int depth, double& toi) {
  if constexpr (std::numeric_limits<long double>::digits > std::numeric_limits<double>::digits) {
    if (lp.counters) ++lp.counters->fallbacks;
    if (!lp.ready) {
      lp.L.kind = lp.S->kind;
      lp.L.d = lp.S->d;
      for (int i = 0; i < 4; ++i) {
        lp.L.s[i] = {lp.S->s[i].x, lp.S->s[i].y, lp.S->s[i].z};
        lp.L.e[i] = {lp.S->e[i].x, lp.S->e[i].y, lp.S->e[i].z};
      }
      coplanarity(lp.L);
      lp.root.f = lp.L.f;
      lp.ng = setup_inside(lp.L, lp.root);
      lp.ready = true;
    }
    Piece<long double> P;
    P.lo = lo, P.hi = hi, P.depth = depth;
    P.ef = restrict_to(lp.root.f, lp.root.ef, P.lo, P.hi, P.f);
    for (int i = 0; i < lp.ng; ++i) P.eg[i] = restrict_to(lp.root.g[i], lp.root.eg[i], P.lo, P.hi, P.g[i]);
    long double t = 0;
    const Outcome r = search(lp.L, lp.root, P, lp.ng, kCcdMaxDepthLong, lp.budget, t, static_cast<LongPass*>(nullptr));
    if (r != Outcome::Miss) toi = round_down(t);
    return r;
  } else {
    toi = lo;
    return Outcome::Undecided;
  }
}

}  // namespace

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

bool ccd_run(CcdKind kind, const CcdPoints& p, double& toi, const CcdOptions& options, CcdCounters* counters) {
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
