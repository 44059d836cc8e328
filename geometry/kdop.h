#pragma once
/// @file Discrete-orientation polytopes (k-DOPs) as small value types, stored as float with
/// outward rounding so that a volume always contains the double geometry it was built from.
///
/// Axes (a point p projects to dot(axis, p)):
///   | slab | 0 | 1 | 2 |  3  |  4  |  5  |  6  |  7  |  8  |
///   | axis | x | y | z | x+y | x-y | x+z | x-z | y+z | y-z |
/// Dop<3> is the axis-aligned box (first three slabs), Dop<9> the 18-DOP.
#include <cmath>
#include <concepts>
#include <cstdint>
#include <cstring>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <mccd/geometry/positions.h>

namespace mccd {

/// The next float toward -inf / +inf (std::nextafter without the library call; finite
/// inputs and infinities as std::nextafter, NaN not expected).
inline float float_down(float f) {
  if (f != f || f == -std::numeric_limits<float>::infinity()) return f;
  if (f == 0.0f) return -std::numeric_limits<float>::denorm_min();
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  u = f > 0 ? u - 1 : u + 1;
  std::memcpy(&f, &u, 4);
  return f;
}
inline float float_up(float f) { return -float_down(-f); }

template <int Slabs>
struct Dop {
  static_assert(Slabs == 3 || Slabs == 9, "Dop supports the AABB (3 slabs) and the 18-DOP (9 slabs)");
  static constexpr int kSlabs = Slabs;
  static constexpr int K = 2 * Slabs;  ///< the k of k-DOP

  float lo[Slabs];  ///< 4 * Slabs bytes: lower bound along each axis
  float hi[Slabs];  ///< 4 * Slabs bytes: upper bound along each axis

  /// The empty volume (contains nothing, overlaps nothing).
  static Dop empty() {
    Dop d;
    for (int i = 0; i < Slabs; ++i) {
      d.lo[i] = std::numeric_limits<float>::infinity();
      d.hi[i] = -std::numeric_limits<float>::infinity();
    }
    return d;
  }

  /// Projections of p on the axes, in double. Each is off the exact value by at most one
  /// rounding (relative 2^-53), which the float conversion in add_point absorbs.
  static void project(const Vec3& p, double out[Slabs]) {
    out[0] = p.x();
    out[1] = p.y();
    out[2] = p.z();
    if constexpr (Slabs == 9) {
      out[3] = p.x() + p.y();
      out[4] = p.x() - p.y();
      out[5] = p.x() + p.z();
      out[6] = p.x() - p.z();
      out[7] = p.y() + p.z();
      out[8] = p.y() - p.z();
    }
  }

  /// Grows the volume to contain p. Bounds are rounded to float and then moved one float
  /// step outward, which covers both the double rounding of the projection (2^-53 relative)
  /// and the float rounding (2^-24 relative): the float bound is strictly outside the exact
  /// projection unless that projection is exactly representable, in which case it is still
  /// outside or on it.
  void add_point(const Vec3& p) {
    double pr[Slabs];
    project(p, pr);
    for (int i = 0; i < Slabs; ++i) {
      const float f = static_cast<float>(pr[i]);
      const float l = float_down(f);
      const float h = float_up(f);
      lo[i] = l < lo[i] ? l : lo[i];
      hi[i] = h > hi[i] ? h : hi[i];
    }
  }

  /// Grows the volume to contain `o` (SSE2 min / max, 4 slabs at a time, for the 18-DOP; the
  /// same comparisons as the loop, so NaN bounds behave alike).
  void merge(const Dop& o) {
#if defined(__SSE2__)
    if constexpr (Slabs == 9) {
      for (int i = 0; i < 8; i += 4) {
        _mm_storeu_ps(lo + i, _mm_min_ps(_mm_loadu_ps(o.lo + i), _mm_loadu_ps(lo + i)));
        _mm_storeu_ps(hi + i, _mm_max_ps(_mm_loadu_ps(o.hi + i), _mm_loadu_ps(hi + i)));
      }
      lo[8] = o.lo[8] < lo[8] ? o.lo[8] : lo[8];
      hi[8] = o.hi[8] > hi[8] ? o.hi[8] : hi[8];
      return;
    }
#endif
    for (int i = 0; i < Slabs; ++i) {
      lo[i] = o.lo[i] < lo[i] ? o.lo[i] : lo[i];
      hi[i] = o.hi[i] > hi[i] ? o.hi[i] : hi[i];
    }
  }

  static Dop merged(const Dop& a, const Dop& b) {
    Dop d = a;
    d.merge(b);
    return d;
  }

  /// Moves every face outward by `d` >= 0 (rounded outward). Two points within distance d
  /// project within d * |axis| <= sqrt(2) d of each other, so inflating both volumes by d
  /// keeps every pair within distance d overlapping.
  void inflate(double d) {
    for (int i = 0; i < Slabs; ++i) {
      lo[i] = float_down(static_cast<float>(lo[i] - d));
      hi[i] = float_up(static_cast<float>(hi[i] + d));
    }
  }

  /// True when the slabs intersect along every axis (touching counts as overlapping).
  /// The 18-DOP's 9 slabs go 4 + 4 at a time in SSE2 registers (every x86-64 has SSE2), the
  /// last one and the AABB's scalar; a NaN bound compares false either way.
  [[gnu::always_inline]] bool overlaps(const Dop& o) const {
#if defined(__SSE2__)
    if constexpr (Slabs == 9) {
      const __m128 sep0 = _mm_or_ps(_mm_cmpgt_ps(_mm_loadu_ps(lo), _mm_loadu_ps(o.hi)),
                                    _mm_cmpgt_ps(_mm_loadu_ps(o.lo), _mm_loadu_ps(hi)));
      const __m128 sep1 = _mm_or_ps(_mm_cmpgt_ps(_mm_loadu_ps(lo + 4), _mm_loadu_ps(o.hi + 4)),
                                    _mm_cmpgt_ps(_mm_loadu_ps(o.lo + 4), _mm_loadu_ps(hi + 4)));
      return (_mm_movemask_ps(_mm_or_ps(sep0, sep1)) == 0) & !(lo[8] > o.hi[8]) & !(o.lo[8] > hi[8]);
    }
#endif
    bool sep = false;
    for (int i = 0; i < Slabs; ++i) sep |= (lo[i] > o.hi[i]) | (o.lo[i] > hi[i]);
    return !sep;
  }

  /// True when the point's exact projections lie inside the slabs (used by tests).
  bool contains(const Vec3& p) const {
    double pr[Slabs];
    project(p, pr);
    for (int i = 0; i < Slabs; ++i)
      if (pr[i] < lo[i] || pr[i] > hi[i]) return false;
    return true;
  }
};

/// What the core needs of a bounding volume (the BVH, the BVTT and the swept volumes are
/// templated on it): an empty volume, growth by a point, a volume and a distance, and a
/// conservative overlap test (touching counts as overlapping).
template <class BV>
concept BoundingVolume = std::copyable<BV> && requires(BV v, const BV& c, const Vec3& p, double d) {
  { BV::empty() } -> std::same_as<BV>;
  { BV::merged(c, c) } -> std::same_as<BV>;
  v.add_point(p);
  v.merge(c);
  v.inflate(d);
  { c.overlaps(c) } -> std::same_as<bool>;
};

using Aabb = Dop<3>;
using Kdop18 = Dop<9>;
static_assert(sizeof(Kdop18) == 72, "18-DOP: 18 floats");
static_assert(sizeof(Aabb) == 24, "AABB: 6 floats");
static_assert(BoundingVolume<Kdop18> && BoundingVolume<Aabb>);

}  // namespace mccd
