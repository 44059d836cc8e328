#pragma once
/// @file Internal: an exact certificate for contacts that touch without crossing, which no
/// sign of the cubic or of the inside functions can certify in floating point: a vertex that
/// passes exactly through an edge of the face, an edge end that passes exactly through the
/// other edge. They arise when the primitives move in one plane, as on grids folded along a
/// grid line. The search (geometry/ccd_search.h) tries it on pieces of 2^-20 and finer, before
/// it would report an undecided contact or start the long-double pass, and on coarser pieces
/// in a window of 2^-20 around where a point crosses a segment's line (window_from).
///
/// A point p(t) touches the open segment (a(t), b(t)) at some t in the window [lo, hi] when:
///  1. the six points p, a, b at t = 0 and t = 1 lie in one plane: three of them (one instant)
///     are certainly not collinear, n = (b - a) x (p - a) having a component n_k beyond its
///     error bound, and the other three are exactly coplanar with them (exact_orient3d of
///     geometry/ccd_exact.h, after a floating-point filter; once one pair of a query is planar
///     and the query's fourth point lies in its plane at both instants, every pair is, and
///     the other pairs need only the first half). Then p(t), a(t), b(t) lie in that
///     plane for every t, w(t) = (b - a)(t) x (p - a)(t) is parallel to n, and since n_k != 0,
///     w_k(t) = 0 exactly when w(t) = 0;
///  2. the quadratic w_k (Bernstein form from the difference vectors, restricted to the window
///     with rigorous bounds) has end values of certain opposite signs: w vanishes at some t*
///     inside the window;
///  3. r(t) = (p - a) . (b - a) and r'(t) = (b - p) . (b - a) are certainly positive over the
///     window. At t*, p - a = lambda (b - a) (w = 0 and b != a), and r, r' > 0 give
///     0 < lambda < 1: p lies strictly inside the segment.
/// For a vertex-face pair the segment is an edge of the face, so the vertex touches the face;
/// for an edge-edge pair it is the other edge, so the edges meet. A certificate proves a
/// contact inside the window and nothing else; failing to find one proves nothing.
///
/// Error bounds (u = 2^-53; coordinates scaled into [2^-60, 2^60] by `load`): every value below
/// is a sum of products of rounded differences of input coordinates, with at most 6 roundings
/// along any path, so it lies within gamma_6 < 6.01 u times the same expression on absolute
/// values; we take 8 u (normal components, 4 roundings), 12 u (the quadratics, 5) and 16 u
/// (the determinant filter, 6), which also covers the rounding of the magnitudes, plus kTiny.
#include <algorithm>
#include <cmath>
#include <utility>

#include <mccd/geometry/ccd_exact.h>
#include <mccd/geometry/ccd_setup.h>

namespace mccd::detail {

namespace touch {

inline Vec3 vec(const V3<double>& v) { return Vec3(v.x, v.y, v.z); }

// The axis k of the largest component of (b - a) x (p - a) that is certainly nonzero, or -1.
inline int normal_axis(const V3<double>& a, const V3<double>& b, const V3<double>& p) {
  const V3<double> D = b - a, E = p - a;
  const V3<double> n = cross(D, E), m = across(vabs(D), vabs(E));
  const double nv[3] = {n.x, n.y, n.z}, mv[3] = {m.x, m.y, m.z};
  int axis = -1;
  double best = 0;
  for (int c = 0; c < 3; ++c) {
    const double v = std::fabs(nv[c]);
    if (v > 8 * kU * mv[c] + kTiny && v > best) axis = c, best = v;
  }
  return axis;
}

// Four points with one coordinate equal lie in a plane normal to that axis, so their
// orientation is exactly zero: no expansion needed (grids folded along a grid line keep one
// coordinate of a line's points equal, bit for bit).
inline bool share_coordinate(const V3<double>& a, const V3<double>& b, const V3<double>& c, const V3<double>& d) {
  return (a.x == b.x && a.x == c.x && a.x == d.x) || (a.y == b.y && a.y == c.y && a.y == d.y) ||
         (a.z == b.z && a.z == c.z && a.z == d.z);
}

inline bool same_point(const V3<double>& a, const V3<double>& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// x lies exactly in the plane through a, b, p (not collinear). A point that has not moved
// (x is a, b or p bit for bit, as for a static or pinned vertex) lies in it without a test.
inline bool in_plane(const V3<double>& a, const V3<double>& b, const V3<double>& p, const V3<double>& x) {
  if (same_point(x, p) || same_point(x, a) || same_point(x, b) || share_coordinate(a, b, p, x)) return true;
  const V3<double> B = b - a, C = p - a, D = x - a;
  const double det = dot(B, cross(C, D));
  if (std::fabs(det) > 16 * kU * absdot(B, across(vabs(C), vabs(D))) + kTiny) return false;
  return exact_orient3d(vec(a), vec(b), vec(p), vec(x)) == 0;
}

// The quadratic x(t) . y(t) for linear x, y (values at t = 0 and 1), and its magnitude.
inline Bern<2> quad_dot(const V3<double>& x0, const V3<double>& x1, const V3<double>& y0, const V3<double>& y1) {
  return {{dot(x0, y0), (dot(x0, y1) + dot(x1, y0)) * 0.5, dot(x1, y1)}};
}
inline Bern<2> quad_absdot(const V3<double>& x0, const V3<double>& x1, const V3<double>& y0, const V3<double>& y1) {
  return {{absdot(x0, y0), (absdot(x0, y1) + absdot(x1, y0)) * 0.5, absdot(x1, y1)}};
}

inline double component(const V3<double>& v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }

// Whether all eight points of a query (four at t = 0, four at t = 1) lie in one plane, found
// from the first point-segment pair whose six points do: its three base points span the
// plane and its other three lie in it, so the query's fourth point at both instants decides.
// Then every other pair whose base points are not collinear lies in that plane too, and its
// exact tests are skipped.
struct SharedPlane {
  const V3<double>* base = nullptr;  ///< the first planar pair's base instant (S.s or S.e)
  int a = 0, b = 0, p = 0;           ///< its base points: the plane through base[a], base[b], base[p]
  int state = 0;                     ///< 0: no planar pair yet; 1: found, not tested; 2: all in one; 3: not

  void found(const V3<double>* at, int j, int k, int i) {
    if (state == 0) base = at, a = j, b = k, p = i, state = 1;
  }
  bool all_in_one(const Setup<double>& S) {
    if (state == 1) {
      const int rest = 6 - a - b - p;  // the point that is not one of the three
      state = in_plane(base[a], base[b], base[p], S.s[rest]) && in_plane(base[a], base[b], base[p], S.e[rest]) ? 2 : 3;
    }
    return state == 2;
  }
};

// Whether the quadratic w (error bound e) has ends of certain opposite signs.
inline bool changes_sign(const Bern<2>& w, double e) {
  return (w.c[0] > e && w.c[2] < -e) || (w.c[0] < -e && w.c[2] > e);
}

// Point i of the query against the segment (j, k): the exact part (the plane) once, then the
// quadratics w_k, r, r' with their error bounds, ready for any window.
struct PointSegment {
  bool planar = false;
  Bern<2> q, r, r2;
  double eq = 0, er = 0, er2 = 0;

  /// `plane`: what the query's earlier pairs found about the plane of all eight points.
  void prepare(const Setup<double>& S, int i, int j, int k, SharedPlane& plane) {
    // 1. The plane, from the instant where the three points are certainly not collinear.
    const V3<double>*base = S.s, *other = S.e;
    int axis = normal_axis(base[j], base[k], base[i]);
    if (axis < 0) {
      std::swap(base, other);
      axis = normal_axis(base[j], base[k], base[i]);
      if (axis < 0) return;
    }
    if (!plane.all_in_one(S)) {
      for (const int x : {i, j, k})
        if (!in_plane(base[j], base[k], base[i], other[x])) return;
      plane.found(base, j, k, i);
    }
    planar = true;
    // 2-3. The quadratics from the difference vectors at t = 0 and t = 1.
    const V3<double> D0 = S.s[k] - S.s[j], D1 = S.e[k] - S.e[j];  // b - a
    const V3<double> E0 = S.s[i] - S.s[j], E1 = S.e[i] - S.e[j];  // p - a
    const V3<double> F0 = S.s[k] - S.s[i], F1 = S.e[k] - S.e[i];  // b - p
    const QuadV<double> w = quad_cross(D0, D1, E0, E1), wm = quad_across(D0, D1, E0, E1);
    q = {{component(w.q[0], axis), component(w.q[1], axis), component(w.q[2], axis)}};
    const Bern<2> qm{{component(wm.q[0], axis), component(wm.q[1], axis), component(wm.q[2], axis)}};
    r = quad_dot(E0, E1, D0, D1);
    r2 = quad_dot(F0, F1, D0, D1);
    eq = error_bound(qm, 12);
    er = error_bound(quad_absdot(E0, E1, D0, D1), 12);
    er2 = error_bound(quad_absdot(F0, F1, D0, D1), 12);
  }

  // Where w_k certainly changes sign on [lo, hi] (dyadic): an estimate of that time from the
  // quadratic restricted there (any estimate is sound: the caller certifies a window), or -1.
  double crossing(double lo, double hi) const {
    if (!planar) return -1;
    Bern<2> w;
    if (!changes_sign(w, restrict_to(q, eq, lo, hi, w))) return -1;
    // w(u) = c0 (1-u)^2 + 2 c1 u (1-u) + c2 u^2 on [0, 1] has one root in (0, 1): the
    // quadratic formula in its stable form (no cancellation between -B and the root of the
    // discriminant), bisection on the sign where rounding puts both roots outside [0, 1].
    const double A = w.c[0] - 2 * w.c[1] + w.c[2], B = 2 * (w.c[1] - w.c[0]), C = w.c[0];
    const double q = -0.5 * (B + std::copysign(std::sqrt(std::max(0.0, B * B - 4 * A * C)), B));
    const double u1 = q / A, u2 = C / q;
    if (u1 >= 0 && u1 <= 1) return lo + u1 * (hi - lo);
    if (u2 >= 0 && u2 <= 1) return lo + u2 * (hi - lo);
    double a = 0, b = 1;
    const bool neg_first = w.c[0] < 0;
    for (int it = 0; it < 30; ++it) {
      const double u = (a + b) / 2, v = 1 - u;
      const double val = w.c[0] * v * v + 2 * w.c[1] * u * v + w.c[2] * u * u;
      ((val < 0) == neg_first ? a : b) = u;
    }
    return lo + (a + b) / 2 * (hi - lo);
  }

  // The touch within [lo, hi] (dyadic, so 1 - lo and 1 - hi are exact).
  bool touches(double lo, double hi) const {
    if (!planar) return false;
    Bern<2> qw, rw, r2w;
    if (!changes_sign(qw, restrict_to(q, eq, lo, hi, qw))) return false;
    return definite_sign(rw, restrict_to(r, er, lo, hi, rw)) > 0 &&
           definite_sign(r2w, restrict_to(r2, er2, lo, hi, r2w)) > 0;
  }
};

}  // namespace touch

/// The certificate for one query, its exact part computed on first use. Vertex-face: the
/// vertex on an edge of the face; edge-edge: an end of either edge on the other edge.
class TouchCertificate {
 public:
  explicit TouchCertificate(const Setup<double>& S) : S_(S) {}

  /// A touch certified in a window starting at `lo` (a dyadic piece start on the grid of
  /// 2^-40, `hi` its end): the piece itself, then [lo, lo + 2^-30] and [lo, lo + 2^-20] within
  /// [0, 1], for a touch just past the piece.
  /// How many point-segment pairs the query has (VF: the vertex and each edge of the face;
  /// EE: each end and the other edge).
  int num_pairs() const { return S_.kind == CcdKind::VertexFace ? 3 : 4; }

  /// For pair c: a window [a, a + 2^-20] on the grid of 2^-20, a >= lo, in which a touch is
  /// certified, found near where the point crosses the segment's line during [lo, hi]: a, or
  /// -1.
  double window_from(int c, double lo, double hi) {
    constexpr double w = 0x1p-20;
    const touch::PointSegment& ps = prepared(c);
    const double t = ps.crossing(lo, hi);
    if (t < 0) return -1;
    const double cell = std::floor(t / w) * w;
    for (const double a : {cell, cell - w})
      if (a >= lo && a + w <= 1 && ps.touches(a, a + w)) return a;
    return -1;
  }

  bool certify(double lo, double hi) {
    double his[3];
    int n = 0;
    his[n++] = hi;
    for (const double w : {0x1p-30, 0x1p-20})
      if (lo + w > his[n - 1] && lo + w <= 1) his[n++] = lo + w;
    for (int c = 0; c < num_pairs(); ++c) {
      const touch::PointSegment& ps = prepared(c);
      for (int m = 0; m < n && ps.planar; ++m)
        if (ps.touches(lo, his[m])) return true;
    }
    return false;
  }

 private:
  /// Pair c, its exact part computed on first use (one pair at a time).
  const touch::PointSegment& prepared(int c) {
    static constexpr int kVF[3][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}};
    static constexpr int kEE[4][3] = {{0, 2, 3}, {1, 2, 3}, {2, 0, 1}, {3, 0, 1}};
    touch::PointSegment& ps = pairs_[c];
    if (!(prepared_ >> c & 1u)) {
      const int* ijk = S_.kind == CcdKind::VertexFace ? kVF[c] : kEE[c];
      ps.prepare(S_, ijk[0], ijk[1], ijk[2], plane_);
      prepared_ |= 1u << c;
    }
    return ps;
  }

  const Setup<double>& S_;
  unsigned prepared_ = 0;  ///< bit c: pairs_[c] prepared
  touch::PointSegment pairs_[4];
  touch::SharedPlane plane_;
};

}  // namespace mccd::detail
