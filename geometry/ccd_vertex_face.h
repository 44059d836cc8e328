#pragma once
/// @file Internal: what is specific to the vertex-face test. With p the vertex and a, b, c the
/// corners of the face, all taken relative to p: A = a - p, B = b - p, C = c - p.
///  - coplanarity: f(t) = det(A, B, C) = A . (B x C), zero iff the four points are coplanar;
///  - inside functions: n = BxC + CxA + AxB and g = n.(BxC), n.(CxA), n.(AxB); at a coplanar
///    time these are u|n|^2, v|n|^2, w|n|^2 with (u, v, w) the barycentric coordinates of p,
///    so contact implies all >= 0, and all > 0 at a coplanar time implies contact;
///  - separation: p against the closest point of the face, then the face normal and its three
///    in-plane edge normals.
#include <mccd/geometry/ccd_setup.h>

namespace mccd::detail::vertex_face {

/// Difference vectors and the cross products of the cubic.
template <class T>
void differences(Setup<T>& S) {
  S.A0 = S.s[1] - S.s[0], S.A1 = S.e[1] - S.e[0];
  S.B0 = S.s[2] - S.s[0], S.B1 = S.e[2] - S.e[0];
  S.C0 = S.s[3] - S.s[0], S.C1 = S.e[3] - S.e[0];
  S.X00 = cross(S.B0, S.C0), S.X01 = cross(S.B0, S.C1), S.X10 = cross(S.B1, S.C0), S.X11 = cross(S.B1, S.C1);
}

/// The pairs (p - corner) checked by the separation test (stage (c) only).
template <class T>
void pairs(Setup<T>& S) {
  S.npairs = 3;
  for (int j = 0; j < 3; ++j) S.D0[j] = S.s[0] - S.s[j + 1], S.D1[j] = S.e[0] - S.e[j + 1];
}

/// The linear factor of the cubic f = a . X: a = A.
template <class T>
void cubic_factor(const Setup<T>& S, V3<T>& a0, V3<T>& a1) {
  a0 = S.A0, a1 = S.A1;
}

/// |n(t)| <= |BxC| + |CxA| + |AxB| <= 3 (bg + ga + ab).
template <class T>
T normal_bound(const Setup<T>& S) {
  return 3 * (S.beta * S.gamma + S.gamma * S.alpha + S.alpha * S.beta);
}

/// The three inside functions on [0, 1] with their error bounds (20 u times the magnitude
/// expression); `aX` receives the magnitude of the cubic's quadratic factor. Returns 3.
template <class T>
int inside(const Setup<T>& S, Piece<T>& P, QuadV<T>& aX) {
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
  return 3;
}

/// The cubic and the inside functions at the instant tau (a multiple of 2^-53 in [0, 1], so
/// that 1 - tau is exact), from the difference vectors interpolated to tau:
/// A(tau) = (1 - tau) A0 + tau A1 (and B, C), X = B x C, Y = C x A, Z = A x B, n = X + Y + Z,
/// f = A . X, g = n . X, n . Y, n . Z.
/// Error (geometry/ccd_fast.h has the argument): every term of A(tau) carries at most 3
/// roundings (the difference of two inputs, the product, the sum), a cross product component
/// 3 + 3 + 2, n 10, f 3 + 8 + 1 + 2 = 14 and g 10 + 8 + 1 + 2 = 21; the magnitudes, taken
/// with every coordinate at its largest absolute value over t in [0, 1] (alpha, beta, gamma
/// for A, B, C), are 6 alpha beta gamma for f (within S.ef = 96 u alpha beta gamma) and the
/// bounds of `inside_magnitudes` for g.
template <class T>
void snapshot(const Setup<T>& S, T tau, Snap<T>& out) {
  const T t1 = 1 - tau;
  const V3<T> A = S.A0 * t1 + S.A1 * tau, B = S.B0 * t1 + S.B1 * tau, C = S.C0 * t1 + S.C1 * tau;
  const V3<T> X = cross(B, C), Y = cross(C, A), Z = cross(A, B);
  const V3<T> n = X + Y + Z;
  out.f = dot(A, X);
  out.g[0] = dot(n, X), out.g[1] = dot(n, Y), out.g[2] = dot(n, Z);
  out.N = n;
}

/// Error bound of the components of the snapshot's n: 10 roundings, magnitude at most
/// 2 (bg + ga + ab) per component.
template <class T>
T normal_error(const Setup<T>& S) {
  return 24 * unit_roundoff<T>() * (S.beta * S.gamma + S.gamma * S.alpha + S.alpha * S.beta) + T(kTiny);
}

/// Bounds M_i on the magnitude expression of g_i at every instant of [0, 1], and on the
/// absolute values of its Bernstein coefficients over [0, 1]: with every component of B x C
/// at most 2 beta gamma (and so on), |n| componentwise at most 2 (bg + ga + ab), and a dot
/// product of three components, M_0 = 12 (bg + ga + ab) bg, M_1 = ... ga, M_2 = ... ab.
/// (A Bernstein coefficient of a product is a convex combination of products of the
/// factors' coefficients, so the same bound holds for them.) Returns 3.
template <class T>
int inside_magnitudes(const Setup<T>& S, T (&M)[4]) {
  const T bg = S.beta * S.gamma, ga = S.gamma * S.alpha, ab = S.alpha * S.beta;
  const T s2 = 12 * (bg + ga + ab);
  M[0] = s2 * bg, M[1] = s2 * ga, M[2] = s2 * ab, M[3] = 0;
  return 3;
}

/// From the closest point of the face (at the positions P) to the vertex.
template <class T>
V3<T> closest_direction(const V3<T> (&P)[4]) {
  using V = V3<T>;
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

/// The face's separating axes at relative positions R (origin at the vertex): its normal and
/// its three in-plane edge normals.
template <class T>
bool separated_by_axes(const Setup<T>& S, const V3<T> (&R)[4], T lo, T hi) {
  const V3<T> ab = R[2] - R[1], bc = R[3] - R[2], ca = R[1] - R[3];
  const V3<T> n = cross(ab, R[3] - R[1]);
  return separated_along(S, n, lo, hi) || separated_along(S, cross(n, ab), lo, hi) ||
         separated_along(S, cross(n, bc), lo, hi) || separated_along(S, cross(n, ca), lo, hi);
}

}  // namespace mccd::detail::vertex_face
