#pragma once
/// @file Internal: the min_distance shortcut of stage (c). With d > 0 the inside functions do
/// not clear pieces (a point outside the face may still be within d of it), so pairs that
/// are within d from the start used to bisect down to the finest pieces and the budgets. They
/// are contacts at t = 0: this proves "within d at t = 0" with a few rigorous floating-point
/// bounds on the input positions (the distance between the primitives is at most the
/// distance between any point of one and any point of the other):
///  - corner to corner (VF: the vertex and each face corner; EE: each end of a and of b);
///  - a corner to the other primitive's segment (VF: the vertex to each face edge; EE: each
///    end to the other edge), when its projection falls inside the segment;
///  - the interior case: at t = 0, every inside function g_i >= 0 means that the projection
///    of the vertex falls in the face (VF), or that the closest points of the two lines lie
///    on both segments (EE); then the distance is |f| / |N| with N the face normal n (VF) or
///    e = da x db (EE) (geometry/ccd_setup.h: at t = 0, g_i = (barycentric or segment
///    parameter) |N|^2, and f = N . (a - p), resp. e . w).
/// A false answer proves nothing; the search then runs as before.
///
/// Rounding: every difference of two inputs rounds once (relative error u); products, sums and
/// squares of such differences are bounded by the usual gamma_k of their rounding depth. Each
/// test compares an upper bound of the squared distance (times a squared length where one is
/// divided out) with d_lo^2 (d_lo <= the scaled d) times a lower bound, with factors (1 +- 16 u)
/// that cover every rounding of the bounds themselves; kTiny covers underflow.
#include <mccd/geometry/ccd_stages.h>

namespace mccd::detail {

// |x - y| <= d for input points x, y: |x - y|^2 (3 squares of one-rounding differences, 2
// sums: relative error within gamma_5) against d^2.
inline bool points_within(V3<double> x, V3<double> y, double d2) {
  const V3<double> u = x - y;
  return dot(u, u) * (1 + 16 * kU) + kTiny <= d2;
}

// dist(x, segment [y0, y1]) <= d, when the projection of x on the line lies on the segment:
// with u = x - y0, v = y1 - y0, w = y1 - x (one rounding each), u . v >= 0 and v . w >= 0
// (projection parameter in [0, 1], each dot within gamma_5 |u|.|v|), and then
// |u x v|^2 <= d^2 |v|^2, the cross product's components within gamma_4 of the magnitude
// |u| x |v| (added to the absolute values before squaring).
inline bool point_segment_within(V3<double> x, V3<double> y0, V3<double> y1, double d2) {
  const V3<double> u = x - y0, v = y1 - y0, w = y1 - x;
  if (!(dot(u, v) >= 8 * kU * absdot(u, v) + kTiny && dot(v, w) >= 8 * kU * absdot(v, w) + kTiny)) return false;
  const V3<double> c = cross(u, v), e = across(vabs(u), vabs(v)) * (8 * kU);
  const V3<double> cu{std::fabs(c.x) + e.x, std::fabs(c.y) + e.y, std::fabs(c.z) + e.z};
  return dot(cu, cu) * (1 + 16 * kU) + kTiny <= d2 * dot(v, v) * (1 - 16 * kU);
}

// The interior case from the snapshot at t = 0: every g_i certainly >= 0 (bounds as in the fast
// path, geometry/ccd_fast.h, without the interval term), and (|f| + ef)^2 <= d^2 |N|_low^2,
// N's components within eN (`normal_error` of the kind) of the computed ones.
template <class Kind>
bool interior_within(const Setup<double>& S, double d2) {
  Snap<double> s0;
  Kind::snapshot(S, 0.0, s0);
  double M[4];
  Kind::inside_magnitudes(S, M);
  for (int i = 0; i < Kind::inside_count; ++i)
    if (!(s0.g[i] >= M[i] * (24 * kU) + 2 * kTiny)) return false;
  const double eN = Kind::normal_error(S);
  const double nx = std::max(0.0, std::fabs(s0.N.x) - eN), ny = std::max(0.0, std::fabs(s0.N.y) - eN),
               nz = std::max(0.0, std::fabs(s0.N.z) - eN);
  const double fu = std::fabs(s0.f) + S.ef;
  return fu * fu * (1 + 16 * kU) + kTiny <= d2 * (nx * nx + ny * ny + nz * nz) * (1 - 16 * kU);
}

/// The primitives are certainly within the minimum distance of each other at t = 0.
template <class Kind>
bool within_at_start(const Setup<double>& S) {
  const double d2 = S.d_lo * S.d_lo * (1 - 4 * kU);
  if (!(d2 > 0)) return false;
  const V3<double>* x = S.s;
  if constexpr (Kind::kind == CcdKind::VertexFace) {
    for (int j = 1; j < 4; ++j)
      if (points_within(x[0], x[j], d2)) return true;
    if (interior_within<Kind>(S, d2)) return true;
    for (int j = 1; j < 4; ++j)
      if (point_segment_within(x[0], x[j], x[j % 3 + 1], d2)) return true;
  } else {
    for (int i = 0; i < 2; ++i)
      for (int j = 2; j < 4; ++j)
        if (points_within(x[i], x[j], d2)) return true;
    if (interior_within<Kind>(S, d2)) return true;
    for (int i = 0; i < 2; ++i)
      if (point_segment_within(x[i], x[2], x[3], d2) || point_segment_within(x[i + 2], x[0], x[1], d2)) return true;
  }
  return false;
}

}  // namespace mccd::detail
