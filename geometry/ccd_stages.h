#pragma once
/// @file Internal: the per-kind stages of an elementary CCD query, dispatched on its kind.
/// Stage (b) builds the coplanarity cubic with its error bound; stage (c) needs the inside
/// functions and the separation test (geometry/ccd_vertex_face.h, geometry/ccd_edge_edge.h).
#include <type_traits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <mccd/geometry/ccd_edge_edge.h>
#include <mccd/geometry/ccd_vertex_face.h>

namespace mccd::detail {

#if defined(__SSE2__)
/// Stage (b) in double with SSE2: each vector at t = 0 and t = 1 side by side in one register
/// pair (lane 0: t = 0), so that the differences, the four cross products and the cubic's
/// dot products take half the instructions. Every lane performs the scalar code's operations
/// in the scalar code's order (no fused operations on x86-64 without FMA), and std::max(a, b)
/// is max_pd(b, a) (both keep a when either is NaN): the results are bit for bit those of the
/// scalar cubic_of.
namespace both_times {
struct Lanes3 {
  __m128d x, y, z;
};
inline Lanes3 load(const V3<double>& s, const V3<double>& e) {
  return {_mm_set_pd(e.x, s.x), _mm_set_pd(e.y, s.y), _mm_set_pd(e.z, s.z)};
}
inline void store(const Lanes3& v, V3<double>& lane0, V3<double>& lane1) {
  _mm_storel_pd(&lane0.x, v.x), _mm_storel_pd(&lane0.y, v.y), _mm_storel_pd(&lane0.z, v.z);
  _mm_storeh_pd(&lane1.x, v.x), _mm_storeh_pd(&lane1.y, v.y), _mm_storeh_pd(&lane1.z, v.z);
}
inline __m128d swapped(__m128d v) { return _mm_shuffle_pd(v, v, 1); }
inline Lanes3 swapped(const Lanes3& v) { return {swapped(v.x), swapped(v.y), swapped(v.z)}; }
inline Lanes3 operator-(const Lanes3& a, const Lanes3& b) {
  return {_mm_sub_pd(a.x, b.x), _mm_sub_pd(a.y, b.y), _mm_sub_pd(a.z, b.z)};
}
inline Lanes3 operator+(const Lanes3& a, const Lanes3& b) {
  return {_mm_add_pd(a.x, b.x), _mm_add_pd(a.y, b.y), _mm_add_pd(a.z, b.z)};
}
inline Lanes3 cross(const Lanes3& a, const Lanes3& b) {
  return {_mm_sub_pd(_mm_mul_pd(a.y, b.z), _mm_mul_pd(a.z, b.y)), _mm_sub_pd(_mm_mul_pd(a.z, b.x), _mm_mul_pd(a.x, b.z)),
          _mm_sub_pd(_mm_mul_pd(a.x, b.y), _mm_mul_pd(a.y, b.x))};
}
inline __m128d dot(const Lanes3& a, const Lanes3& b) {
  return _mm_add_pd(_mm_add_pd(_mm_mul_pd(a.x, b.x), _mm_mul_pd(a.y, b.y)), _mm_mul_pd(a.z, b.z));
}
/// std::max(amax(lane 0), amax(lane 1)), as the scalar code computes it.
inline double amax(const Lanes3& a) {
  const __m128d m = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
  const __m128d x = _mm_and_pd(a.x, m), y = _mm_and_pd(a.y, m), z = _mm_and_pd(a.z, m);
  const __m128d v = _mm_max_pd(_mm_max_pd(z, y), x);
  return std::max(_mm_cvtsd_f64(v), _mm_cvtsd_f64(swapped(v)));
}

/// The differences, cross products, magnitudes and cubic of stage (b) into S.
template <bool VertexFace>
void coplanarity(Setup<double>& S) {
  const Lanes3 p0 = load(S.s[0], S.e[0]), p1 = load(S.s[1], S.e[1]), p2 = load(S.s[2], S.e[2]),
               p3 = load(S.s[3], S.e[3]);
  Lanes3 A, B, C, Xd, Xs;  // Xd: (X00, X11), Xs: (X01, X10)
  if constexpr (VertexFace) {
    A = p1 - p0, B = p2 - p0, C = p3 - p0;
    Xd = cross(B, C), Xs = cross(B, swapped(C));
  } else {
    A = p1 - p0, B = p3 - p2, C = p2 - p0;
    Xd = cross(A, B), Xs = cross(A, swapped(B));
  }
  store(A, S.A0, S.A1), store(B, S.B0, S.B1), store(C, S.C0, S.C1);
  store(Xd, S.X00, S.X11), store(Xs, S.X01, S.X10);
  S.alpha = amax(A), S.beta = amax(B), S.gamma = amax(C);
  // cubic(a0, a1, X00, X01 + X10, X11) with a = A (vertex-face) or C (edge-edge).
  const Lanes3& a = VertexFace ? A : C;
  const __m128d ends = dot(a, Xd);                           // (c0, c3)
  const __m128d mid = dot(a, Xs + swapped(Xs));               // (a0.(X01+X10), a1.(X01+X10))
  const __m128d cross_terms = dot(a, swapped(Xd));            // (a0.X11, a1.X00)
  const __m128d inner = _mm_div_pd(_mm_add_pd(mid, swapped(cross_terms)), _mm_set1_pd(3.0));  // (c1, c2)
  _mm_storel_pd(&S.f.c[0], ends), _mm_storeh_pd(&S.f.c[3], ends);
  _mm_storel_pd(&S.f.c[1], inner), _mm_storeh_pd(&S.f.c[2], inner);
}
}  // namespace both_times
#endif

/// Stage (b) for a kind known at compile time: the coplanarity cubic in Bernstein form with
/// its error bound. Error: 6 products of three differences per determinant, at most 9
/// roundings: |err| <= gamma_9 * 6 alpha beta gamma < 96 u alpha beta gamma (alpha, beta,
/// gamma: largest absolute coordinate of the three difference vectors at t = 0 and 1). With a
/// minimum distance d, dN = d times a bound on the length of the cubic's normal, the margin by
/// which the cubic must clear zero. The separation pairs of stage (c) are not computed.
/// The differences, cross products, magnitudes (alpha, beta, gamma) and the cubic of stage (b),
/// one vector at a time (any T; the reference of both_times::coplanarity).
template <CcdKind K, class T>
void cubic_of(Setup<T>& S) {
  V3<T> a0, a1;
  if constexpr (K == CcdKind::VertexFace) {
    vertex_face::differences(S);
    vertex_face::cubic_factor(S, a0, a1);
  } else {
    edge_edge::differences(S);
    edge_edge::cubic_factor(S, a0, a1);
  }
  S.alpha = std::max(amax(S.A0), amax(S.A1));
  S.beta = std::max(amax(S.B0), amax(S.B1));
  S.gamma = std::max(amax(S.C0), amax(S.C1));
  S.f = cubic(a0, a1, S.X00, S.X01 + S.X10, S.X11);
}

template <CcdKind K, class T>
void coplanarity_of(Setup<T>& S) {
  constexpr T u = unit_roundoff<T>();
  constexpr bool vf = K == CcdKind::VertexFace;
#if defined(__SSE2__)
  if constexpr (std::is_same_v<T, double>)
    both_times::coplanarity<vf>(S);
  else
#endif
    cubic_of<K>(S);
  S.ef = T(96) * u * (S.alpha * S.beta * S.gamma) + T(kTiny);
  S.dN = 0;
  if (S.d > 0) {
    if constexpr (vf)
      S.dN = S.d * vertex_face::normal_bound(S) * (1 + 16 * u);
    else
      S.dN = S.d * edge_edge::normal_bound(S) * (1 + 16 * u);
  }
}

/// The separation pairs of stage (c), for a kind known at compile time.
template <CcdKind K, class T>
void pairs_of(Setup<T>& S) {
  if constexpr (K == CcdKind::VertexFace)
    vertex_face::pairs(S);
  else
    edge_edge::pairs(S);
}

/// Stage (b) and the separation pairs, dispatched on the run-time kind.
template <class T>
void coplanarity(Setup<T>& S) {
  if (S.kind == CcdKind::VertexFace) {
    coplanarity_of<CcdKind::VertexFace>(S);
    pairs_of<CcdKind::VertexFace>(S);
  } else {
    coplanarity_of<CcdKind::EdgeEdge>(S);
    pairs_of<CcdKind::EdgeEdge>(S);
  }
}

/// The per-kind functions of the fast path (geometry/ccd_fast.h) as a type, so that it is
/// compiled once per kind with no run-time dispatch.
template <CcdKind K>
struct KindOps {
  static constexpr CcdKind kind = K;
  static constexpr int inside_count = K == CcdKind::VertexFace ? 3 : 4;  ///< number of g_i
  template <class T>
  static void snapshot(const Setup<T>& S, T tau, Snap<T>& out) {
    if constexpr (K == CcdKind::VertexFace)
      vertex_face::snapshot(S, tau, out);
    else
      edge_edge::snapshot(S, tau, out);
  }
  template <class T>
  static int inside_magnitudes(const Setup<T>& S, T (&M)[4]) {
    if constexpr (K == CcdKind::VertexFace)
      return vertex_face::inside_magnitudes(S, M);
    else
      return edge_edge::inside_magnitudes(S, M);
  }
  /// A bound on the snapshot's f error at tau, often much tighter than S.ef: 16 u (gamma_14
  /// and the rounding of the bound) times the magnitude of the triple product, the sum of its
  /// six monomials in absolute value (the same for VF, A . (B x C), and EE, w . (da x db) with
  /// A, B, C = da, db, w), each vector's components interpolated in absolute value:
  /// (1 - tau) |A0| + tau |A1| bounds the magnitude of the interpolated terms.
  template <class T>
  static T f_error(const Setup<T>& S, T tau) {
    const T t1 = 1 - tau;
    const V3<T> A = vabs(S.A0) * t1 + vabs(S.A1) * tau, B = vabs(S.B0) * t1 + vabs(S.B1) * tau,
                C = vabs(S.C0) * t1 + vabs(S.C1) * tau;
    return 16 * unit_roundoff<T>() * dot(A, across(B, C)) + T(kTiny);
  }
  template <class T>
  static T normal_error(const Setup<T>& S) {
    if constexpr (K == CcdKind::VertexFace)
      return vertex_face::normal_error(S);
    else
      return edge_edge::normal_error(S);
  }
};

/// Computes the inside functions on [0, 1] and, for every polynomial of stage (c) (the cubic
/// included), an error bound from its magnitude expression: gamma_k times the same expression
/// on absolute values (k roundings at most: 9 for the cubic, 12 for the quartics; we take
/// 16 u and 20 u, which also covers the rounding of the magnitudes themselves). Returns the
/// number of inside functions.
template <class T>
int setup_inside(const Setup<T>& S, Piece<T>& P) {
  QuadV<T> aX;
  V3<T> a0, a1;
  int ng;
  if (S.kind == CcdKind::VertexFace) {
    ng = vertex_face::inside(S, P, aX);
    vertex_face::cubic_factor(S, a0, a1);
  } else {
    ng = edge_edge::inside(S, P, aX);
    edge_edge::cubic_factor(S, a0, a1);
  }
  P.ef = std::min(S.ef, error_bound(cubic(vabs(a0), vabs(a1), aX.q[0], aX.q[1] * T(2), aX.q[2]), 16));
  return ng;
}

/// Candidate separating directions at the middle of the piece: the closest-point direction,
/// then the separating axes of the two convex primitives. Any direction is sound: the test
/// itself is rigorous; good directions only make it succeed sooner.
template <class T>
bool separated(const Setup<T>& S, T lo, T hi) {
  const T t = (lo + hi) / 2;
  const bool vf = S.kind == CcdKind::VertexFace;
  V3<T> P[4];
  for (int i = 0; i < 4; ++i) P[i] = lerp(S.s[i], S.e[i], t);
  if (separated_along(S, vf ? vertex_face::closest_direction(P) : edge_edge::closest_direction(P), lo, hi))
    return true;
  // Relative coordinates (origin at point 0) keep the rounding of the axes relative to u.
  V3<T> R[4];
  for (int i = 0; i < 4; ++i) R[i] = lerp(S.s[i] - S.s[0], S.e[i] - S.e[0], t);
  return vf ? vertex_face::separated_by_axes(S, R, lo, hi) : edge_edge::separated_by_axes(S, R, lo, hi);
}

}  // namespace mccd::detail
