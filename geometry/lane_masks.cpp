#include <mccd/geometry/lane_masks.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>

#include <mccd/geometry/error.h>

#if defined(__x86_64__)
#define MCCD_LANES_X86 1
#include <immintrin.h>
#endif

#if defined(__GNUC__) && !defined(__clang__)
// GCC notes that the kernels' lambdas and helpers return vector registers under a wider
// instruction set than the file's (-Wpsabi): they are inlined into their kernel, no such call
// crosses an ABI.
// GCC 12 also reads _mm512_undefined_* in its own headers as uninitialized (its bug 105593).
#pragma GCC diagnostic ignored "-Wpsabi"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif

namespace mccd::detail {

// Each instruction set's kernels live in a namespace of their own (so no inline function is
// shared between sets) and, past SSE2, in a region compiled for that set only: nothing from
// these regions runs unless the processor has the set (lane_kernels_for()).

namespace {
/// LaneKernels::merge_lanes a lane at a time (the sets without a permute across lanes).
void merge_lanes_by_lane(const std::int16_t* rows, unsigned stride, unsigned slabs,
                         const std::uint8_t (*sources)[kMaxLanes], unsigned k, unsigned n, std::int16_t* out,
                         unsigned out_stride) {
  for (unsigned r = 0; r < 2 * slabs; ++r) {
    const std::int16_t* in = rows + r * stride;
    std::int16_t* o = out + r * out_stride;
    const bool lower = r < slabs;
    for (unsigned j = 0; j < n; ++j) {
      std::int16_t v = in[sources[0][j]];
      for (unsigned s = 1; s < k; ++s) {
        const std::int16_t w = in[sources[s][j]];
        v = lower ? (w < v ? w : v) : (w > v ? w : v);
      }
      o[j] = v;
    }
  }
}
}  // namespace

namespace lanes_scalar {
struct Ops {
  static constexpr unsigned kLanes = 8;
  static constexpr SimdLevel kLevel = SimdLevel::Scalar;
  using Acc = std::uint32_t;  // the lanes overlapping
  static Acc slab(const std::int16_t* lo, const std::int16_t* hi, std::int16_t olo, std::int16_t ohi) {
    Acc acc = 0;
    for (unsigned k = 0; k < kLanes; ++k) acc |= Acc(!(lo[k] > ohi || olo > hi[k])) << k;
    return acc;
  }
  static Acc join(Acc a, Acc b) { return a & b; }
  static std::uint32_t bits(Acc acc) { return acc; }
  using Row = const std::int16_t*;
  static Row row(const std::int16_t* p) { return p; }
  static Acc slab_row(Row lo, Row hi, std::int16_t olo, std::int16_t ohi) { return slab(lo, hi, olo, ohi); }
  static constexpr auto merge = &merge_lanes_by_lane;
};
struct DOps {
  static constexpr unsigned kLanes = 1;
  using V = double;
  static V load(const double* p) { return *p; }
  static V zero() { return 0.0; }
  static V set1(double x) { return x; }
  static V add(V a, V b) { return a + b; }
  static V sub(V a, V b) { return a - b; }
  static V mul(V a, V b) { return a * b; }
  static V div(V a, V b) { return a / b; }
  static V max(V a, V b) { return a > b ? a : b; }
  static V abs(V a) { return std::fabs(a); }
  static V neg(V a) { return -a; }
  static unsigned gt(V a, V b) { return a > b; }
  static unsigned ge(V a, V b) { return a >= b; }
  static unsigned eq(V a, V b) { return a == b; }
  static void store(double* p, V a) { *p = a; }
  static V select(unsigned bits, V a, V b) { return bits & 1u ? a : b; }
  /// floor(a) for a in [0, 2^62) as the scalar code computes it (a cast); other values (lanes
  /// whose result is not used) pass unchanged
  static V floor_nonneg(V a) { return a >= 0 && a < 0x1p62 ? static_cast<double>(static_cast<std::int64_t>(a)) : a; }
  static V exponent(V a) { return std::bit_cast<double>(std::bit_cast<std::uint64_t>(a) & 0x7ff0000000000000ull); }
  static V sqrt(V a) { return std::sqrt(a); }
  static V copysign(V a, V b) { return std::copysign(a, b); }
};
constexpr decltype(LaneKernels::vertex_quarters) kVertexQuarters = nullptr;
#include "lane_masks_kernels.inl"
}  // namespace lanes_scalar

#if MCCD_LANES_X86
namespace lanes_sse2 {
struct Ops {
  static constexpr unsigned kLanes = 8;
  static constexpr SimdLevel kLevel = SimdLevel::Sse2;
  using Acc = __m128i;  // the lanes apart
  static Acc slab(const std::int16_t* lo, const std::int16_t* hi, std::int16_t olo, std::int16_t ohi) {
    const __m128i l = _mm_loadu_si128(reinterpret_cast<const __m128i*>(lo));
    const __m128i h = _mm_loadu_si128(reinterpret_cast<const __m128i*>(hi));
    return _mm_or_si128(_mm_cmpgt_epi16(l, _mm_set1_epi16(ohi)), _mm_cmpgt_epi16(_mm_set1_epi16(olo), h));
  }
  static Acc join(Acc a, Acc b) { return _mm_or_si128(a, b); }
  using Row = __m128i;
  static Row row(const std::int16_t* p) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p)); }
  static Acc slab_row(Row l, Row h, std::int16_t olo, std::int16_t ohi) {
    return _mm_or_si128(_mm_cmpgt_epi16(l, _mm_set1_epi16(ohi)), _mm_cmpgt_epi16(_mm_set1_epi16(olo), h));
  }
  static std::uint32_t bits(Acc acc) {
    return ~static_cast<std::uint32_t>(_mm_movemask_epi8(_mm_packs_epi16(acc, _mm_setzero_si128()))) & 0xFFu;
  }
  static constexpr auto merge = &merge_lanes_by_lane;
};
struct DOps {
  static constexpr unsigned kLanes = 2;
  using V = __m128d;
  static V load(const double* p) { return _mm_load_pd(p); }
  static V zero() { return _mm_setzero_pd(); }
  static V set1(double x) { return _mm_set1_pd(x); }
  static V add(V a, V b) { return _mm_add_pd(a, b); }
  static V sub(V a, V b) { return _mm_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm_mul_pd(a, b); }
  static V div(V a, V b) { return _mm_div_pd(a, b); }
  static V max(V a, V b) { return _mm_max_pd(a, b); }
  static V abs(V a) { return _mm_andnot_pd(_mm_set1_pd(-0.0), a); }
  static V neg(V a) { return _mm_xor_pd(_mm_set1_pd(-0.0), a); }
  static unsigned gt(V a, V b) { return static_cast<unsigned>(_mm_movemask_pd(_mm_cmpgt_pd(a, b))); }
  static unsigned ge(V a, V b) { return static_cast<unsigned>(_mm_movemask_pd(_mm_cmpge_pd(a, b))); }
  static unsigned eq(V a, V b) { return static_cast<unsigned>(_mm_movemask_pd(_mm_cmpeq_pd(a, b))); }
  static void store(double* p, V a) { _mm_store_pd(p, a); }
  static V select(unsigned bits, V a, V b) {
    const V m = _mm_castsi128_pd(_mm_set_epi64x(bits & 2u ? -1 : 0, bits & 1u ? -1 : 0));
    return _mm_or_pd(_mm_and_pd(m, a), _mm_andnot_pd(m, b));
  }
  /// floor(a) for a in [0, 2^62), lane by lane as the scalar code (SSE2 rounds to int32 only);
  /// other values (lanes whose result is not used) pass unchanged
  static V floor_nonneg(V a) {
    alignas(16) double x[2];
    _mm_store_pd(x, a);
    for (double& v : x)
      if (v >= 0 && v < 0x1p62) v = static_cast<double>(static_cast<std::int64_t>(v));
    return _mm_load_pd(x);
  }
  static V exponent(V a) { return _mm_and_pd(a, _mm_castsi128_pd(_mm_set1_epi64x(0x7ff0000000000000LL))); }
  static V sqrt(V a) { return _mm_sqrt_pd(a); }
  static V copysign(V a, V b) {
    const V sign = _mm_set1_pd(-0.0);
    return _mm_or_pd(_mm_andnot_pd(sign, a), _mm_and_pd(sign, b));
  }
};
constexpr decltype(LaneKernels::vertex_quarters) kVertexQuarters = nullptr;
#include "lane_masks_kernels.inl"
}  // namespace lanes_sse2

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx,avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx,avx2")
#endif
namespace lanes_avx2 {
struct Ops {
  static constexpr unsigned kLanes = 16;
  static constexpr SimdLevel kLevel = SimdLevel::Avx2;
  using Acc = __m256i;  // the lanes apart
  static Acc slab(const std::int16_t* lo, const std::int16_t* hi, std::int16_t olo, std::int16_t ohi) {
    const __m256i l = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(lo));
    const __m256i h = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(hi));
    return _mm256_or_si256(_mm256_cmpgt_epi16(l, _mm256_set1_epi16(ohi)),
                           _mm256_cmpgt_epi16(_mm256_set1_epi16(olo), h));
  }
  static Acc join(Acc a, Acc b) { return _mm256_or_si256(a, b); }
  using Row = __m256i;
  static Row row(const std::int16_t* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
  static Acc slab_row(Row l, Row h, std::int16_t olo, std::int16_t ohi) {
    return _mm256_or_si256(_mm256_cmpgt_epi16(l, _mm256_set1_epi16(ohi)), _mm256_cmpgt_epi16(_mm256_set1_epi16(olo), h));
  }
  static std::uint32_t bits(Acc acc) {
    // packed with zeros, per 128-bit half: lanes 0-7 in bytes 0-7, lanes 8-15 in bytes 16-23
    const std::uint32_t m =
        static_cast<std::uint32_t>(_mm256_movemask_epi8(_mm256_packs_epi16(acc, _mm256_setzero_si256())));
    return ~((m & 0xFFu) | (m >> 8 & 0xFF00u)) & 0xFFFFu;
  }
  static constexpr auto merge = &merge_lanes_by_lane;
};
struct DOps {
  static constexpr unsigned kLanes = 4;
  using V = __m256d;
  static V load(const double* p) { return _mm256_load_pd(p); }
  static V zero() { return _mm256_setzero_pd(); }
  static V set1(double x) { return _mm256_set1_pd(x); }
  static V add(V a, V b) { return _mm256_add_pd(a, b); }
  static V sub(V a, V b) { return _mm256_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm256_mul_pd(a, b); }
  static V div(V a, V b) { return _mm256_div_pd(a, b); }
  static V max(V a, V b) { return _mm256_max_pd(a, b); }
  static V abs(V a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
  static V neg(V a) { return _mm256_xor_pd(_mm256_set1_pd(-0.0), a); }
  static unsigned gt(V a, V b) { return static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(a, b, _CMP_GT_OQ))); }
  static unsigned ge(V a, V b) { return static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(a, b, _CMP_GE_OQ))); }
  static unsigned eq(V a, V b) { return static_cast<unsigned>(_mm256_movemask_pd(_mm256_cmp_pd(a, b, _CMP_EQ_OQ))); }
  static void store(double* p, V a) { _mm256_store_pd(p, a); }
  static V select(unsigned bits, V a, V b) {
    const __m256i lane = _mm256_set_epi64x(8, 4, 2, 1);
    const __m256i m = _mm256_cmpeq_epi64(_mm256_and_si256(_mm256_set1_epi64x(bits), lane), lane);
    return _mm256_blendv_pd(b, a, _mm256_castsi256_pd(m));
  }
  /// floor(a) for a >= 0 (exact: the value the scalar code's cast to int64 gives below 2^62)
  static V floor_nonneg(V a) { return _mm256_round_pd(a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC); }
  static V exponent(V a) { return _mm256_and_pd(a, _mm256_castsi256_pd(_mm256_set1_epi64x(0x7ff0000000000000LL))); }
  static V sqrt(V a) { return _mm256_sqrt_pd(a); }
  static V copysign(V a, V b) {
    const V sign = _mm256_set1_pd(-0.0);
    return _mm256_or_pd(_mm256_andnot_pd(sign, a), _mm256_and_pd(sign, b));
  }
};
/// LaneKernels::vertex_quarters: four vertices at a time (lanes_avx512's, a register half as
/// wide).
void vertex_quarters(const double* x0, const double* x1, const std::uint32_t* vertex_of_slot, std::size_t n,
                     double min_distance, std::uint64_t skip, float* out, const CoarseOut* coarse) {
  const __m256d quarter = _mm256_set1_pd(0.25), half = _mm256_set1_pd(0.5), three = _mm256_set1_pd(0.75);
  const __m256d scale = _mm256_set1_pd(0x1p-48), distance = _mm256_set1_pd(min_distance);
  const __m128 zero = _mm_setzero_ps(), top = _mm_set1_ps(65535.0f);
  const __m128i middle = _mm_set1_epi32(32768);
  alignas(16) std::int32_t lower[9][4], upper[9][4];
  auto abs = [](__m256d v) { return DOps::abs(v); };
  // kdop.h's floats_down / floats_up
  const __m128 big = _mm_set1_ps(std::numeric_limits<float>::max()), ulp = _mm_set1_ps(0x1p-23f);
  const __m128 tiny = _mm_set1_ps(std::numeric_limits<float>::min()), sign = _mm_set1_ps(-0.0f);
  auto floats_down = [&](__m128 f) {
    f = _mm_min_ps(f, big);
    return _mm_sub_ps(f, _mm_add_ps(_mm_mul_ps(_mm_andnot_ps(sign, f), ulp), tiny));
  };
  auto floats_up = [&](__m128 f) { return _mm_xor_ps(floats_down(_mm_xor_ps(f, sign)), sign); };
  for (std::size_t g = 0; g < n; g += 4) {
    const unsigned m = n - g >= 4 ? 4u : static_cast<unsigned>(n - g);
    alignas(16) std::int32_t at[4];
    for (unsigned i = 0; i < 4; ++i) at[i] = static_cast<std::int32_t>(3 * vertex_of_slot[g + (i < m ? i : 0)]);
    const __m128i idx = _mm_load_si128(reinterpret_cast<const __m128i*>(at));
    const __m256d ax = _mm256_i32gather_pd(x0, idx, 8), ay = _mm256_i32gather_pd(x0 + 1, idx, 8);
    const __m256d az = _mm256_i32gather_pd(x0 + 2, idx, 8), bx = _mm256_i32gather_pd(x1, idx, 8);
    const __m256d by = _mm256_i32gather_pd(x1 + 1, idx, 8), bz = _mm256_i32gather_pd(x1 + 2, idx, 8);
    const __m256d pa[9] = {ax, ay, az, _mm256_add_pd(ax, ay), _mm256_sub_pd(ax, ay), _mm256_add_pd(ax, az),
                           _mm256_sub_pd(ax, az), _mm256_add_pd(ay, az), _mm256_sub_pd(ay, az)};
    const __m256d pb[9] = {bx, by, bz, _mm256_add_pd(bx, by), _mm256_sub_pd(bx, by), _mm256_add_pd(bx, bz),
                           _mm256_sub_pd(bx, bz), _mm256_add_pd(by, bz), _mm256_sub_pd(by, bz)};
    const __m256d largest = _mm256_max_pd(_mm256_max_pd(_mm256_max_pd(abs(ax), abs(ay)), abs(az)),
                                          _mm256_max_pd(_mm256_max_pd(abs(bx), abs(by)), abs(bz)));
    const __m256d margin = _mm256_add_pd(_mm256_mul_pd(largest, scale), distance);
    const unsigned stored = ~static_cast<unsigned>(skip >> g) & ((1u << m) - 1u);
    for (int s = 0; s < 9; ++s) {
      const __m256d p0 = pa[s], p4 = pb[s], d = _mm256_sub_pd(p4, p0);
      const __m256d p1 = _mm256_add_pd(p0, _mm256_mul_pd(quarter, d));
      const __m256d p2 = _mm256_add_pd(p0, _mm256_mul_pd(half, d));
      const __m256d p3 = _mm256_add_pd(p0, _mm256_mul_pd(three, d));
      __m128 lo[4] = {floats_down(_mm256_cvtpd_ps(_mm256_sub_pd(_mm256_min_pd(p0, p1), margin))),
                      floats_down(_mm256_cvtpd_ps(_mm256_sub_pd(_mm256_min_pd(p1, p2), margin))),
                      floats_down(_mm256_cvtpd_ps(_mm256_sub_pd(_mm256_min_pd(p2, p3), margin))),
                      floats_down(_mm256_cvtpd_ps(_mm256_sub_pd(_mm256_min_pd(p3, p4), margin)))};
      __m128 hi[4] = {floats_up(_mm256_cvtpd_ps(_mm256_add_pd(_mm256_max_pd(p0, p1), margin))),
                      floats_up(_mm256_cvtpd_ps(_mm256_add_pd(_mm256_max_pd(p1, p2), margin))),
                      floats_up(_mm256_cvtpd_ps(_mm256_add_pd(_mm256_max_pd(p2, p3), margin))),
                      floats_up(_mm256_cvtpd_ps(_mm256_add_pd(_mm256_max_pd(p3, p4), margin)))};
      if (coarse) {  // the merge of the quarters (QuarterDop::whole's order), on the grid
        const __m128 whole_lo = _mm_min_ps(lo[3], _mm_min_ps(lo[2], _mm_min_ps(lo[1], lo[0])));
        const __m128 whole_hi = _mm_max_ps(hi[3], _mm_max_ps(hi[2], _mm_max_ps(hi[1], hi[0])));
        const __m128 o = _mm_set1_ps(coarse->origin[s]), k = _mm_set1_ps(coarse->scale[s]);
        const __m128 ql = _mm_min_ps(_mm_max_ps(_mm_mul_ps(_mm_sub_ps(whole_lo, o), k), zero), top);
        _mm_store_si128(reinterpret_cast<__m128i*>(lower[s]), _mm_sub_epi32(_mm_cvttps_epi32(ql), middle));
        const __m128 qh = _mm_max_ps(_mm_min_ps(_mm_mul_ps(_mm_sub_ps(whole_hi, o), k), top), zero);
        __m128i t = _mm_cvttps_epi32(qh);
        t = _mm_sub_epi32(t, _mm_castps_si128(_mm_cmplt_ps(_mm_cvtepi32_ps(t), qh)));
        _mm_store_si128(reinterpret_cast<__m128i*>(upper[s]), _mm_sub_epi32(t, middle));
      }
      _MM_TRANSPOSE4_PS(lo[0], lo[1], lo[2], lo[3]);  // register i: vertex i's quarters 0-3
      _MM_TRANSPOSE4_PS(hi[0], hi[1], hi[2], hi[3]);
      for (unsigned i = 0; i < m; ++i) {
        if (!(stored >> i & 1u)) continue;
        float* q = out + 72 * (g + i) + 8 * s;
        _mm_store_ps(q, lo[i]);
        _mm_store_ps(q + 4, hi[i]);
      }
    }
    if (coarse)
      for (unsigned i = 0; i < m; ++i) {
        if (!(stored >> i & 1u)) continue;
        CoarseDop& c = coarse->out[g + i];
        for (int s = 0; s < 16; ++s) {
          c.lo[s] = s < 9 ? static_cast<std::int16_t>(lower[s][i]) : std::int16_t(0);
          c.hi[s] = s < 9 ? static_cast<std::int16_t>(upper[s][i]) : std::int16_t(0);
        }
      }
  }
}
constexpr decltype(LaneKernels::vertex_quarters) kVertexQuarters = &vertex_quarters;
#include "lane_masks_kernels.inl"
}  // namespace lanes_avx2
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx,avx2,avx512f,avx512bw"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx,avx2,avx512f,avx512bw")
#endif
namespace lanes_avx512 {
struct Ops {
  static constexpr unsigned kLanes = 32;
  static constexpr SimdLevel kLevel = SimdLevel::Avx512;
  using Acc = __mmask32;  // the lanes overlapping
  static Acc slab(const std::int16_t* lo, const std::int16_t* hi, std::int16_t olo, std::int16_t ohi) {
    const __mmask32 below = _mm512_cmp_epi16_mask(_mm512_loadu_si512(lo), _mm512_set1_epi16(ohi), _MM_CMPINT_LE);
    return _mm512_mask_cmp_epi16_mask(below, _mm512_set1_epi16(olo), _mm512_loadu_si512(hi), _MM_CMPINT_LE);
  }
  static Acc join(Acc a, Acc b) { return _kand_mask32(a, b); }
  using Row = __m512i;
  static Row row(const std::int16_t* p) { return _mm512_loadu_si512(p); }
  static Acc slab_row(Row l, Row h, std::int16_t olo, std::int16_t ohi) {
    const __mmask32 below = _mm512_cmp_epi16_mask(l, _mm512_set1_epi16(ohi), _MM_CMPINT_LE);
    return _mm512_mask_cmp_epi16_mask(below, _mm512_set1_epi16(olo), h, _MM_CMPINT_LE);
  }
  static std::uint32_t bits(Acc acc) { return acc; }
  /// A row's 64 lanes in two registers, each out chunk of 32 lanes gathered from them with a
  /// two-source permute.
  static void merge(const std::int16_t* rows, unsigned stride, unsigned slabs, const std::uint8_t (*sources)[kMaxLanes],
                    unsigned k, unsigned n, std::int16_t* out, unsigned out_stride) {
    for (unsigned c = 0; c < n; c += 32) {
      __m512i idx[3];
      for (unsigned s = 0; s < k; ++s)
        idx[s] = _mm512_cvtepu8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(sources[s] + c)));
      const __mmask32 keep = n - c >= 32 ? ~__mmask32(0) : (__mmask32(1) << (n - c)) - 1;
      for (unsigned r = 0; r < 2 * slabs; ++r) {
        const __m512i lo = _mm512_loadu_si512(rows + r * stride), hi = _mm512_loadu_si512(rows + r * stride + 32);
        __m512i v = _mm512_permutex2var_epi16(lo, idx[0], hi);
        for (unsigned s = 1; s < k; ++s) {
          const __m512i w = _mm512_permutex2var_epi16(lo, idx[s], hi);
          v = r < slabs ? _mm512_min_epi16(v, w) : _mm512_max_epi16(v, w);
        }
        _mm512_mask_storeu_epi16(out + r * out_stride + c, keep, v);
      }
    }
  }
};
struct DOps {
  static constexpr unsigned kLanes = 8;
  using V = __m512d;
  static V load(const double* p) { return _mm512_load_pd(p); }
  static V zero() { return _mm512_setzero_pd(); }
  static V set1(double x) { return _mm512_set1_pd(x); }
  static V add(V a, V b) { return _mm512_add_pd(a, b); }
  static V sub(V a, V b) { return _mm512_sub_pd(a, b); }
  static V mul(V a, V b) { return _mm512_mul_pd(a, b); }
  static V div(V a, V b) { return _mm512_div_pd(a, b); }
  static V max(V a, V b) { return _mm512_max_pd(a, b); }
  static V abs(V a) { return bits_op<false>(a, 0x7fffffffffffffffLL); }
  static V neg(V a) { return bits_op<true>(a, static_cast<long long>(0x8000000000000000ULL)); }
  /// a's bits and (Xor: xor) `mask`'s (AVX-512F has no floating-point and / xor)
  template <bool Xor>
  static V bits_op(V a, long long mask) {
    const __m512i x = _mm512_castpd_si512(a), m = _mm512_set1_epi64(mask);
    return _mm512_castsi512_pd(Xor ? _mm512_xor_si512(x, m) : _mm512_and_si512(x, m));
  }
  static unsigned gt(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_GT_OQ); }
  static unsigned ge(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ); }
  static unsigned eq(V a, V b) { return _mm512_cmp_pd_mask(a, b, _CMP_EQ_OQ); }
  static void store(double* p, V a) { _mm512_store_pd(p, a); }
  static V select(unsigned bits, V a, V b) { return _mm512_mask_blend_pd(static_cast<__mmask8>(bits), b, a); }
  /// floor(a) for a >= 0 (exact: the value the scalar code's cast to int64 gives below 2^62)
  static V floor_nonneg(V a) { return _mm512_roundscale_pd(a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC); }
  static V exponent(V a) { return bits_op<false>(a, 0x7ff0000000000000LL); }
  static V sqrt(V a) { return _mm512_sqrt_pd(a); }
  static V copysign(V a, V b) {
    const __m512i sign = _mm512_set1_epi64(static_cast<long long>(0x8000000000000000ULL));
    return _mm512_castsi512_pd(_mm512_or_si512(_mm512_andnot_si512(sign, _mm512_castpd_si512(a)),
                                               _mm512_and_si512(sign, _mm512_castpd_si512(b))));
  }
};
/// LaneKernels::vertex_quarters: eight vertices at a time, SweptVolumes::vertex_volumes's
/// operations on each (its SSE2 path: two slabs a register there, a vertex a lane here).
void vertex_quarters(const double* x0, const double* x1, const std::uint32_t* vertex_of_slot, std::size_t n,
                     double min_distance, std::uint64_t skip, float* out, const CoarseOut* coarse) {
  const __m512d quarter = _mm512_set1_pd(0.25), half = _mm512_set1_pd(0.5), three = _mm512_set1_pd(0.75);
  const __m512d scale = _mm512_set1_pd(0x1p-48), distance = _mm512_set1_pd(min_distance);
  const __m256 big = _mm256_set1_ps(std::numeric_limits<float>::max()), ulp = _mm256_set1_ps(0x1p-23f);
  const __m256 tiny = _mm256_set1_ps(std::numeric_limits<float>::min()), sign = _mm256_set1_ps(-0.0f);
  // kdop.h's floats_down / floats_up, eight floats at a time
  auto down = [&](__m256 f) {
    f = _mm256_min_ps(f, big);
    return _mm256_sub_ps(f, _mm256_add_ps(_mm256_mul_ps(_mm256_andnot_ps(sign, f), ulp), tiny));
  };
  auto up = [&](__m256 f) { return _mm256_xor_ps(down(_mm256_xor_ps(f, sign)), sign); };
  auto abs = [](__m512d v) { return DOps::abs(v); };
  // coarse_volumes.h's CoarseGrid::quantize, eight floats at a time
  const __m256 zero = _mm256_setzero_ps(), top = _mm256_set1_ps(65535.0f);
  const __m256i middle = _mm256_set1_epi32(32768);
  alignas(32) std::int32_t lower[9][8], upper[9][8];
  for (std::size_t g = 0; g < n; g += 8) {
    const unsigned m = n - g >= 8 ? 8u : static_cast<unsigned>(n - g);
    alignas(32) std::uint32_t at[8];
    for (unsigned i = 0; i < 8; ++i) at[i] = 3 * vertex_of_slot[g + (i < m ? i : 0)];
    const __m256i idx = _mm256_load_si256(reinterpret_cast<const __m256i*>(at));
    const __m512d ax = _mm512_i32gather_pd(idx, x0, 8), ay = _mm512_i32gather_pd(idx, x0 + 1, 8);
    const __m512d az = _mm512_i32gather_pd(idx, x0 + 2, 8), bx = _mm512_i32gather_pd(idx, x1, 8);
    const __m512d by = _mm512_i32gather_pd(idx, x1 + 1, 8), bz = _mm512_i32gather_pd(idx, x1 + 2, 8);
    const __m512d pa[9] = {ax,
                           ay,
                           az,
                           _mm512_add_pd(ax, ay),
                           _mm512_sub_pd(ax, ay),
                           _mm512_add_pd(ax, az),
                           _mm512_sub_pd(ax, az),
                           _mm512_add_pd(ay, az),
                           _mm512_sub_pd(ay, az)};
    const __m512d pb[9] = {bx,
                           by,
                           bz,
                           _mm512_add_pd(bx, by),
                           _mm512_sub_pd(bx, by),
                           _mm512_add_pd(bx, bz),
                           _mm512_sub_pd(bx, bz),
                           _mm512_add_pd(by, bz),
                           _mm512_sub_pd(by, bz)};
    // the largest coordinate (a maximum: exact in any order) times 2^-48, plus the distance
    const __m512d largest = _mm512_max_pd(_mm512_max_pd(_mm512_max_pd(abs(ax), abs(ay)), abs(az)),
                                          _mm512_max_pd(_mm512_max_pd(abs(bx), abs(by)), abs(bz)));
    const __m512d margin = _mm512_add_pd(_mm512_mul_pd(largest, scale), distance);
    const unsigned stored = ~static_cast<unsigned>(skip >> g) & ((1u << m) - 1u);
    for (int s = 0; s < 9; ++s) {
      const __m512d p0 = pa[s], p4 = pb[s], d = _mm512_sub_pd(p4, p0);
      const __m512d p1 = _mm512_add_pd(p0, _mm512_mul_pd(quarter, d));
      const __m512d p2 = _mm512_add_pd(p0, _mm512_mul_pd(half, d));
      const __m512d p3 = _mm512_add_pd(p0, _mm512_mul_pd(three, d));
      const __m256 lo[4] = {down(_mm512_cvtpd_ps(_mm512_sub_pd(_mm512_min_pd(p0, p1), margin))),
                            down(_mm512_cvtpd_ps(_mm512_sub_pd(_mm512_min_pd(p1, p2), margin))),
                            down(_mm512_cvtpd_ps(_mm512_sub_pd(_mm512_min_pd(p2, p3), margin))),
                            down(_mm512_cvtpd_ps(_mm512_sub_pd(_mm512_min_pd(p3, p4), margin)))};
      const __m256 hi[4] = {up(_mm512_cvtpd_ps(_mm512_add_pd(_mm512_max_pd(p0, p1), margin))),
                            up(_mm512_cvtpd_ps(_mm512_add_pd(_mm512_max_pd(p1, p2), margin))),
                            up(_mm512_cvtpd_ps(_mm512_add_pd(_mm512_max_pd(p2, p3), margin))),
                            up(_mm512_cvtpd_ps(_mm512_add_pd(_mm512_max_pd(p3, p4), margin)))};
      // quarters 0-3 of each vertex side by side: a 4 x 8 transpose, vertex i in the low half
      // of register i (i < 4) or the high half of register i - 4
      __m256 tl[4], th[4];
      auto transpose = [](const __m256* q, __m256* t) {
        const __m256 a = _mm256_unpacklo_ps(q[0], q[1]), b = _mm256_unpackhi_ps(q[0], q[1]);
        const __m256 c = _mm256_unpacklo_ps(q[2], q[3]), e = _mm256_unpackhi_ps(q[2], q[3]);
        t[0] = _mm256_shuffle_ps(a, c, _MM_SHUFFLE(1, 0, 1, 0));
        t[1] = _mm256_shuffle_ps(a, c, _MM_SHUFFLE(3, 2, 3, 2));
        t[2] = _mm256_shuffle_ps(b, e, _MM_SHUFFLE(1, 0, 1, 0));
        t[3] = _mm256_shuffle_ps(b, e, _MM_SHUFFLE(3, 2, 3, 2));
      };
      transpose(lo, tl);
      transpose(hi, th);
      if (coarse) {  // the merge of the quarters (QuarterDop::whole's order), on the grid
        const __m256 whole_lo = _mm256_min_ps(lo[3], _mm256_min_ps(lo[2], _mm256_min_ps(lo[1], lo[0])));
        const __m256 whole_hi = _mm256_max_ps(hi[3], _mm256_max_ps(hi[2], _mm256_max_ps(hi[1], hi[0])));
        const __m256 o = _mm256_set1_ps(coarse->origin[s]), k = _mm256_set1_ps(coarse->scale[s]);
        const __m256 ql = _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(whole_lo, o), k), zero), top);
        _mm256_store_si256(reinterpret_cast<__m256i*>(lower[s]), _mm256_sub_epi32(_mm256_cvttps_epi32(ql), middle));
        const __m256 qh = _mm256_max_ps(_mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(whole_hi, o), k), top), zero);
        __m256i t = _mm256_cvttps_epi32(qh);
        t = _mm256_sub_epi32(t, _mm256_castps_si256(_mm256_cmp_ps(_mm256_cvtepi32_ps(t), qh, _CMP_LT_OQ)));
        _mm256_store_si256(reinterpret_cast<__m256i*>(upper[s]), _mm256_sub_epi32(t, middle));
      }
      for (unsigned i = 0; i < m; ++i) {
        if (!(stored >> i & 1u)) continue;
        float* q = out + 72 * (g + i) + 8 * s;
        const __m128 l = i < 4 ? _mm256_castps256_ps128(tl[i]) : _mm256_extractf128_ps(tl[i - 4], 1);
        const __m128 h = i < 4 ? _mm256_castps256_ps128(th[i]) : _mm256_extractf128_ps(th[i - 4], 1);
        _mm_store_ps(q, l);
        _mm_store_ps(q + 4, h);
      }
    }
    if (coarse)
      for (unsigned i = 0; i < m; ++i) {
        if (!(stored >> i & 1u)) continue;
        CoarseDop& c = coarse->out[g + i];
        for (int s = 0; s < 16; ++s) {
          c.lo[s] = s < 9 ? static_cast<std::int16_t>(lower[s][i]) : std::int16_t(0);
          c.hi[s] = s < 9 ? static_cast<std::int16_t>(upper[s][i]) : std::int16_t(0);
        }
      }
  }
}
constexpr decltype(LaneKernels::vertex_quarters) kVertexQuarters = &vertex_quarters;
#include "lane_masks_kernels.inl"
}  // namespace lanes_avx512
#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
#endif  // MCCD_LANES_X86

namespace {

bool supported(SimdLevel level) {
  switch (level) {
    case SimdLevel::Scalar:
      return true;
#if MCCD_LANES_X86
    case SimdLevel::Sse2:
      return true;  // part of x86-64
    case SimdLevel::Avx2:
      return __builtin_cpu_supports("avx") && __builtin_cpu_supports("avx2");
    case SimdLevel::Avx512:
      return __builtin_cpu_supports("avx") && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("avx512f") &&
             __builtin_cpu_supports("avx512bw");
#endif
    default:
      return false;
  }
}

const LaneKernels* table(SimdLevel level) {
  switch (level) {
    case SimdLevel::Scalar:
      return &lanes_scalar::kernels;
#if MCCD_LANES_X86
    case SimdLevel::Sse2:
      return &lanes_sse2::kernels;
    case SimdLevel::Avx2:
      return &lanes_avx2::kernels;
    case SimdLevel::Avx512:
      return &lanes_avx512::kernels;
#endif
    default:
      return nullptr;
  }
}

/// The best supported level, or the environment's MCCD_SIMD when it names a lower one.
const LaneKernels* initial() {
  SimdLevel level = best_simd_level();
  if (const char* env = std::getenv("MCCD_SIMD"); env && *env)
    if (const std::optional<SimdLevel> asked = parse_simd_level(env); asked && *asked < level) level = *asked;
  return table(level);
}

std::atomic<const LaneKernels*>& current() {
  static std::atomic<const LaneKernels*> kernels{initial()};
  return kernels;
}

}  // namespace

SimdLevel best_simd_level() {
  for (SimdLevel l : {SimdLevel::Avx512, SimdLevel::Avx2, SimdLevel::Sse2})
    if (table(l) && supported(l)) return l;
  return SimdLevel::Scalar;
}

const LaneKernels* lane_kernels_for(SimdLevel level) { return supported(level) ? table(level) : nullptr; }

const LaneKernels& lane_kernels() { return *current().load(std::memory_order_relaxed); }

void select_simd_level(SimdLevel level) {
  const LaneKernels* k = lane_kernels_for(level);
  if (!k) throw Error(std::string("SIMD level ") + to_string(level) + ": not supported by this processor or build");
  current().store(k, std::memory_order_relaxed);
}

const char* to_string(SimdLevel level) {
  switch (level) {
    case SimdLevel::Scalar:
      return "scalar";
    case SimdLevel::Sse2:
      return "sse2";
    case SimdLevel::Avx2:
      return "avx2";
    case SimdLevel::Avx512:
      return "avx512";
  }
  return "?";
}

std::optional<SimdLevel> parse_simd_level(const std::string& name) {
  for (SimdLevel l : {SimdLevel::Scalar, SimdLevel::Sse2, SimdLevel::Avx2, SimdLevel::Avx512})
    if (name == to_string(l)) return l;
  return std::nullopt;
}

}  // namespace mccd::detail
