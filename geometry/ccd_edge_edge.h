#pragma once
/// @file Internal: what is specific to the edge-edge test. With edges [a0, a1] and [b0, b1]:
/// da = a1 - a0, db = b1 - b0, w = b0 - a0.
///  - coplanarity: f(t) = det(da, db, w) = w . (da x db);
///  - inside functions: e = da x db and g = (w x db).e, -((b0 - a1) x db).e, (w x da).e,
///    (da x (b1 - a0)).e; if the segments meet at a0 + s da = b0 + r db these are s|e|^2,
///    (1-s)|e|^2, r|e|^2, (1-r)|e|^2;
///  - separation: along the closest points of the two segments, then e and its in-plane
///    normals to each edge.
#include <mccd/geometry/ccd_setup.h>

namespace mccd::detail::edge_edge {

/// Difference vectors (A = da, B = db, C = w) and the cross products of the cubic.
template <class T>
void differences(Setup<T>& S) {
  S.A0 = S.s[1] - S.s[0], S.A1 = S.e[1] - S.e[0];  // da
  S.B0 = S.s[3] - S.s[2], S.B1 = S.e[3] - S.e[2];  // db
  S.C0 = S.s[2] - S.s[0], S.C1 = S.e[2] - S.e[0];  // w
  S.X00 = cross(S.A0, S.B0), S.X01 = cross(S.A0, S.B1), S.X10 = cross(S.A1, S.B0), S.X11 = cross(S.A1, S.B1);
}

/// The pairs (end of b - end of a) checked by the separation test (stage (c) only; the
/// snapshots also use D[1] = b0 - a1 and D[2] = b1 - a0).
template <class T>
void pairs(Setup<T>& S) {
  S.npairs = 4;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) S.D0[2 * j + i] = S.s[2 + j] - S.s[i], S.D1[2 * j + i] = S.e[2 + j] - S.e[i];
}

/// The linear factor of the cubic f = a . X: a = w.
template <class T>
void cubic_factor(const Setup<T>& S, V3<T>& a0, V3<T>& a1) {
  a0 = S.C0, a1 = S.C1;
}

/// |e(t)| <= 3 ab.
template <class T>
T normal_bound(const Setup<T>& S) {
  return 3 * S.alpha * S.beta;
}

/// The four inside functions on [0, 1] with their error bounds (20 u times the magnitude
/// expression); `aX` receives the magnitude of e. Returns 4.
template <class T>
int inside(const Setup<T>& S, Piece<T>& P, QuadV<T>& aX) {
  using V = V3<T>;
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
  return 4;
}

/// The cubic and the inside functions at the instant tau (a multiple of 2^-53 in [0, 1]), from
/// the difference vectors interpolated to tau: da, db, w and v = b0 - a1, z = b1 - a0 (the
/// separation pairs D[1], D[2]); e = da x db, f = w . e, g = (w x db).e, -(v x db).e,
/// (w x da).e, (da x z).e. Roundings (as for the vertex-face snapshot): f 14, g 8 + 8 + 1 + 2
/// = 19; magnitudes 6 alpha beta gamma for f (within S.ef) and `inside_magnitudes` for g.
template <class T>
void snapshot(const Setup<T>& S, T tau, Snap<T>& out) {
  const T t1 = 1 - tau;
  const V3<T> da = S.A0 * t1 + S.A1 * tau, db = S.B0 * t1 + S.B1 * tau, w = S.C0 * t1 + S.C1 * tau;
  const V3<T> v = S.D0[1] * t1 + S.D1[1] * tau, z = S.D0[2] * t1 + S.D1[2] * tau;
  const V3<T> e = cross(da, db);
  out.f = dot(w, e);
  out.g[0] = dot(cross(w, db), e), out.g[1] = -dot(cross(v, db), e);
  out.g[2] = dot(cross(w, da), e), out.g[3] = dot(cross(da, z), e);
  out.N = e;
}

/// Error bound of the components of the snapshot's e: 8 roundings, magnitude at most
/// 2 alpha beta per component.
template <class T>
T normal_error(const Setup<T>& S) {
  return 20 * unit_roundoff<T>() * (S.alpha * S.beta) + T(kTiny);
}

/// Bounds M_i on the magnitude expressions of the g_i at every instant (and on their Bernstein
/// coefficients over [0, 1]): |e| componentwise at most 2 alpha beta, |w x db| at most
/// 2 gamma beta, and so on with nu, zeta the largest coordinates of v and z: M_0 = 12 ab bg,
/// M_1 = 12 ab nu beta, M_2 = 12 ab ga, M_3 = 12 ab alpha zeta. Returns 4.
template <class T>
int inside_magnitudes(const Setup<T>& S, T (&M)[4]) {
  const T nu = std::max(amax(S.D0[1]), amax(S.D1[1])), zeta = std::max(amax(S.D0[2]), amax(S.D1[2]));
  const T ab12 = 12 * S.alpha * S.beta;
  M[0] = ab12 * (S.beta * S.gamma), M[1] = ab12 * (nu * S.beta), M[2] = ab12 * (S.gamma * S.alpha),
  M[3] = ab12 * (S.alpha * zeta);
  return 4;
}

/// Between the closest points of the segments (clamped; degenerate cases tolerated).
template <class T>
V3<T> closest_direction(const V3<T> (&P)[4]) {
  using V = V3<T>;
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

/// The axes at relative positions R (origin at a0): da x db and its in-plane normals to each
/// edge.
template <class T>
bool separated_by_axes(const Setup<T>& S, const V3<T> (&R)[4], T lo, T hi) {
  const V3<T> da = R[1], db = R[3] - R[2];
  const V3<T> e = cross(da, db);
  return separated_along(S, e, lo, hi) || separated_along(S, cross(e, da), lo, hi) ||
         separated_along(S, cross(e, db), lo, hi);
}

}  // namespace mccd::detail::edge_edge
