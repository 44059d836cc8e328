#pragma once
/// @file Internal: coarse volumes, k-DOPs with 16-bit integer bounds on a grid, for the first
/// test of feature pairs (a sixth of a float k-DOP's bytes; 32 of them to an AVX-512 register).
///
/// A grid maps each slab's axis onto [0, 65535]: q(v) = (v - origin) * scale, computed in
/// float. A lower bound becomes the integer at or below q(v), an upper bound the one at or
/// above, both clamped to [0, 65535] (a NaN lower bound becomes 0, a NaN upper bound 65535),
/// then moved down by 32768 to be signed. Every step of this is monotone (a float subtraction
/// and multiplication by a positive number round monotonically, as do floor, ceiling and
/// clamping), so when two float volumes overlap along a slab (a.lo <= b.hi) their coarse ones do
/// too: coarse volumes never separate what the float ones do not. They only ever serve to skip
/// pairs that the float volumes would separate as well. The grid only decides how tight they
/// are: bounds outside its box are clamped, which loosens them but is still conservative.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <mccd/geometry/kdop.h>

namespace mccd::detail {

template <int Slabs>
struct CoarseGrid {
  float origin[Slabs];
  float scale[Slabs];

  /// A grid of every slab over [lo, hi] (lo <= hi, finite).
  static CoarseGrid over(const Dop<Slabs>& box) {
    CoarseGrid g;
    for (int s = 0; s < Slabs; ++s) {
      const double lo = box.lo[s], hi = box.hi[s];
      const double extent = std::max(hi - lo, 1e-30);
      g.origin[s] = static_cast<float>(lo);
      g.scale[s] = static_cast<float>(65535.0 / extent);
    }
    return g;
  }

  /// `d`'s coarse volume: out[s] its lower bound along slab s, out[Slabs + s] its upper.
  void quantize(const Dop<Slabs>& d, std::int16_t out[2 * Slabs]) const {
    int s = 0;
#if defined(__SSE2__)
    const __m128 zero = _mm_setzero_ps(), top = _mm_set1_ps(65535.0f);
    const __m128i half = _mm_set1_epi32(32768);
    for (; s + 4 <= Slabs; s += 4) {
      const __m128 o = _mm_loadu_ps(origin + s), k = _mm_loadu_ps(scale + s);
      // lower: max(v, 0) (NaN gives 0), then min(., 65535); truncation is the floor there
      __m128 lo = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(d.lo + s), o), k);
      lo = _mm_min_ps(_mm_max_ps(lo, zero), top);
      const __m128i lq = _mm_sub_epi32(_mm_cvttps_epi32(lo), half);
      // upper: min(v, 65535) (NaN gives 65535), then max(., 0); the ceiling is the
      // truncation plus one where it lies below
      __m128 hi = _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(d.hi + s), o), k);
      hi = _mm_max_ps(_mm_min_ps(hi, top), zero);
      __m128i ht = _mm_cvttps_epi32(hi);
      ht = _mm_sub_epi32(ht, _mm_castps_si128(_mm_cmplt_ps(_mm_cvtepi32_ps(ht), hi)));  // -(-1)
      const __m128i hq = _mm_sub_epi32(ht, half);
      alignas(16) std::int32_t l4[4], h4[4];
      _mm_store_si128(reinterpret_cast<__m128i*>(l4), lq);
      _mm_store_si128(reinterpret_cast<__m128i*>(h4), hq);
      for (int i = 0; i < 4; ++i) {
        out[s + i] = static_cast<std::int16_t>(l4[i]);
        out[Slabs + s + i] = static_cast<std::int16_t>(h4[i]);
      }
    }
#endif
    for (; s < Slabs; ++s) {
      out[s] = lower(d.lo[s], s);
      out[Slabs + s] = upper(d.hi[s], s);
    }
  }

  /// One bound, as quantize() computes it.
  std::int16_t lower(float v, int s) const {
    float q = (v - origin[s]) * scale[s];
    q = q > 0.0f ? q : 0.0f;  // NaN: 0
    q = q < 65535.0f ? q : 65535.0f;
    return static_cast<std::int16_t>(static_cast<std::int32_t>(q) - 32768);
  }
  std::int16_t upper(float v, int s) const {
    float q = (v - origin[s]) * scale[s];
    q = q < 65535.0f ? q : 65535.0f;  // NaN: 65535
    q = q > 0.0f ? q : 0.0f;
    std::int32_t t = static_cast<std::int32_t>(q);
    t += static_cast<float>(t) < q;
    return static_cast<std::int16_t>(t - 32768);
  }
};

/// The grid of a sequence of steps: kept while it holds the step's positions and is not much
/// larger than they need (so that static meshes and repeating leaves keep their coarse volumes'
/// meaning), else made anew around them, half as large again on each side.
template <int Slabs>
class GridKeeper {
 public:
  /// The grid for positions within the box [lo, hi] (finite, lo <= hi on every axis).
  const CoarseGrid<Slabs>& fit(const double lo[3], const double hi[3]) {
    Dop<Slabs> want;
    const auto set = [&](int s, double l, double h) {
      want.lo[s] = static_cast<float>(l);
      want.hi[s] = static_cast<float>(h);
    };
    for (int k = 0; k < 3; ++k) set(k, lo[k], hi[k]);
    if constexpr (Slabs == 9) {  // the box's projections on the diagonal axes (geometry/kdop.h)
      set(3, lo[0] + lo[1], hi[0] + hi[1]);
      set(4, lo[0] - hi[1], hi[0] - lo[1]);
      set(5, lo[0] + lo[2], hi[0] + hi[2]);
      set(6, lo[0] - hi[2], hi[0] - lo[2]);
      set(7, lo[1] + lo[2], hi[1] + hi[2]);
      set(8, lo[1] - hi[2], hi[1] - lo[2]);
    }
    float largest = 0;
    for (int s = 0; s < Slabs; ++s) largest = std::max(largest, want.hi[s] - want.lo[s]);
    const float least = largest > 0 ? largest * 0x1p-10f : 1.0f;  // a flat scene's thin slabs
    bool keep = set_;
    for (int s = 0; s < Slabs && keep; ++s) {
      const float need = std::max(want.hi[s] - want.lo[s], least);
      keep = want.lo[s] >= box_.lo[s] && want.hi[s] <= box_.hi[s] && box_.hi[s] - box_.lo[s] <= 4 * need;
    }
    if (!keep) {
      for (int s = 0; s < Slabs; ++s) {
        const float grow = std::max(want.hi[s] - want.lo[s], least) / 2;
        box_.lo[s] = want.lo[s] - grow;
        box_.hi[s] = want.hi[s] + grow;
      }
      grid_ = CoarseGrid<Slabs>::over(box_);
      set_ = true;
    }
    return grid_;
  }

 private:
  CoarseGrid<Slabs> grid_{};
  Dop<Slabs> box_{};
  bool set_ = false;
};

}  // namespace mccd::detail
