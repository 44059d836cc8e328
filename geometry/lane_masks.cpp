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
#include <mccd/geometry/quarter_volumes.h>

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
/// The ids of W items of K ids each, in a row from `ids`: `ids` itself when it holds all W
/// (m == W), else `copy` filled with its m items and the first one repeated (the lanes past m
/// of a vector kernel's last group).
template <unsigned W, unsigned K>
const std::uint32_t* padded(const std::uint32_t* ids, unsigned m, std::uint32_t (&copy)[W * K]) {
  if (m >= W) return ids;
  for (unsigned i = 0; i < W; ++i)
    for (unsigned k = 0; k < K; ++k) copy[K * i + k] = ids[K * (i < m ? i : 0) + k];
  return copy;
}
/// LaneKernels::vertex_quarters's coarse volumes: lane i < m of `stored` from its nine lower
/// and upper bounds (lower[s][i], upper[s][i]), the unused bounds 0, into out[i].
template <unsigned W>
void write_coarse(const std::int32_t (&lower)[9][W], const std::int32_t (&upper)[9][W], unsigned m, unsigned stored,
                  CoarseDop* out) {
  for (unsigned i = 0; i < m; ++i) {
    if (!(stored >> i & 1u)) continue;
    for (int s = 0; s < 16; ++s) {
      out[i].lo[s] = s < 9 ? static_cast<std::int16_t>(lower[s][i]) : std::int16_t(0);
      out[i].hi[s] = s < 9 ? static_cast<std::int16_t>(upper[s][i]) : std::int16_t(0);
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
  static V min(V a, V b) { return a < b ? a : b; }
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
  /// base[at[i]] in lane i (`at` aligned to the register's lanes of 64-bit offsets)
  static V gather(const double* base, const std::int64_t* at) { return base[at[0]]; }
};
constexpr decltype(LaneKernels::vertex_quarters) kVertexQuarters = nullptr;
constexpr decltype(LaneKernels::merge_quarters) kMergeQuarters = nullptr;
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
  static V min(V a, V b) { return _mm_min_pd(a, b); }
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
  static V gather(const double* base, const std::int64_t* at) { return _mm_set_pd(base[at[1]], base[at[0]]); }
};
constexpr decltype(LaneKernels::vertex_quarters) kVertexQuarters = nullptr;
constexpr decltype(LaneKernels::merge_quarters) kMergeQuarters = nullptr;
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
  static V min(V a, V b) { return _mm256_min_pd(a, b); }
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
  static V gather(const double* base, const std::int64_t* at) {
    return _mm256_i64gather_pd(base, _mm256_load_si256(reinterpret_cast<const __m256i*>(at)), 8);
  }
};
/// LaneKernels::vertex_quarters's operations (geometry/vertex_quarters_kernel.inl).
struct VOps {
  static constexpr unsigned kLanes = 4;
  using D = DOps::V;  // the double operations are DOps'
  using F = __m128;
  using I = __m128i;
  /// The offsets 3 v of the vertices in slots[0, m) (the lanes past m repeat the first).
  using Offsets = __m256i;
  static Offsets offsets(const std::uint32_t* slots, unsigned m) {
    std::uint32_t copy[kLanes];
    const auto* at = reinterpret_cast<const __m128i*>(padded<kLanes, 1>(slots, m, copy));
    const __m256i v = _mm256_cvtepu32_epi64(_mm_loadu_si128(at));
    return _mm256_add_epi64(v, _mm256_slli_epi64(v, 1));
  }
  static D gather(const double* base, Offsets at) { return _mm256_i64gather_pd(base, at, 8); }
  static F cvt(D a) { return _mm256_cvtpd_ps(a); }
  static F fset(float x) { return _mm_set1_ps(x); }
  static F fsub(F a, F b) { return _mm_sub_ps(a, b); }
  static F fmul(F a, F b) { return _mm_mul_ps(a, b); }
  static F fmin(F a, F b) { return _mm_min_ps(a, b); }
  static F fmax(F a, F b) { return _mm_max_ps(a, b); }
  static I cvtt(F a) { return _mm_cvttps_epi32(a); }
  static F fceil(F a) { return _mm_ceil_ps(a); }
  static I isub(I a, I b) { return _mm_sub_epi32(a, b); }
  static I iset(std::int32_t x) { return _mm_set1_epi32(x); }
  static void istore(std::int32_t* p, I a) { _mm_store_si128(reinterpret_cast<__m128i*>(p), a); }
  static void write_coarse(const std::int32_t (&lower)[9][kLanes], const std::int32_t (&upper)[9][kLanes], unsigned m,
                           unsigned stored, CoarseDop* out) {
    detail::write_coarse(lower, upper, m, stored, out);
  }
  static void store(const F (&lo)[4], const F (&hi)[4], unsigned m, unsigned stored, float* out) {
    F l[4] = {lo[0], lo[1], lo[2], lo[3]}, h[4] = {hi[0], hi[1], hi[2], hi[3]};
    _MM_TRANSPOSE4_PS(l[0], l[1], l[2], l[3]);  // register i: lane i's quarters 0-3
    _MM_TRANSPOSE4_PS(h[0], h[1], h[2], h[3]);
    for (unsigned i = 0; i < m; ++i)
      if (stored >> i & 1u) _mm_store_ps(out + 72 * i, l[i]), _mm_store_ps(out + 72 * i + 4, h[i]);
  }
};
#include "vertex_quarters_kernel.inl"
constexpr decltype(LaneKernels::vertex_quarters) kVertexQuarters = &vertex_quarters;
constexpr decltype(LaneKernels::merge_quarters) kMergeQuarters = nullptr;
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
  static V min(V a, V b) { return _mm512_min_pd(a, b); }
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
  static V gather(const double* base, const std::int64_t* at) {
    return _mm512_i64gather_pd(_mm512_load_si512(at), base, 8);
  }
  /// gather_points' offsets 3 id of each of the K ids of 8 items (items past m repeat the
  /// first), a register per k: the ids loaded as they lie, picked apart by permutes.
  using Offsets = __m512i;
  template <unsigned K>
  static void offsets(const std::uint32_t (*ids)[K], unsigned m, Offsets (&out)[K]) {
    static_assert(K == 3 || K == 4, "two registers hold 8 items' ids");
    std::uint32_t copy[8 * K];
    const std::uint32_t* p = padded<8, K>(ids[0], m, copy);
    const __m512i a = _mm512_loadu_si512(p);
    const __m512i b = _mm512_maskz_loadu_epi32(static_cast<__mmask16>((1u << (8 * K - 16)) - 1u), p + 16);
    const __m512i item = _mm512_set_epi32(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0);
    const __m512i first = _mm512_mullo_epi32(item, _mm512_set1_epi32(K));  // item i's first id
    for (unsigned k = 0; k < K; ++k) {
      const __m512i pick = _mm512_add_epi32(first, _mm512_set1_epi32(static_cast<int>(k)));
      const __m512i w = _mm512_cvtepu32_epi64(_mm512_castsi512_si256(_mm512_permutex2var_epi32(a, pick, b)));
      out[k] = _mm512_add_epi64(w, _mm512_slli_epi64(w, 1));
    }
  }
  static V gather_at(const double* base, Offsets at) { return _mm512_i64gather_pd(at, base, 8); }
};
/// LaneKernels::vertex_quarters's operations (geometry/vertex_quarters_kernel.inl).
struct VOps {
  static constexpr unsigned kLanes = 8;
  using D = DOps::V;  // the double operations are DOps'
  using F = __m256;
  using I = __m256i;
  /// The offsets 3 v of the vertices in slots[0, m) (the lanes past m repeat the first).
  using Offsets = __m512i;
  static Offsets offsets(const std::uint32_t* slots, unsigned m) {
    std::uint32_t copy[kLanes];
    const auto* at = reinterpret_cast<const __m256i*>(padded<kLanes, 1>(slots, m, copy));
    const __m512i v = _mm512_cvtepu32_epi64(_mm256_loadu_si256(at));
    return _mm512_add_epi64(v, _mm512_slli_epi64(v, 1));
  }
  static D gather(const double* base, Offsets at) { return _mm512_i64gather_pd(at, base, 8); }
  static F cvt(D a) { return _mm512_cvtpd_ps(a); }
  static F fset(float x) { return _mm256_set1_ps(x); }
  static F fsub(F a, F b) { return _mm256_sub_ps(a, b); }
  static F fmul(F a, F b) { return _mm256_mul_ps(a, b); }
  static F fmin(F a, F b) { return _mm256_min_ps(a, b); }
  static F fmax(F a, F b) { return _mm256_max_ps(a, b); }
  static I cvtt(F a) { return _mm256_cvttps_epi32(a); }
  static F fceil(F a) { return _mm256_ceil_ps(a); }
  static I isub(I a, I b) { return _mm256_sub_epi32(a, b); }
  static I iset(std::int32_t x) { return _mm256_set1_epi32(x); }
  static void istore(std::int32_t* p, I a) { _mm256_store_si256(reinterpret_cast<__m256i*>(p), a); }
  /// The free write_coarse's records, each put together in a register by three permutes of
  /// the bounds narrowed to 16 bits (lower slabs 0-7, upper slabs 0-7, slab 8 of both) and
  /// written whole.
  static void write_coarse(const std::int32_t (&lower)[9][kLanes], const std::int32_t (&upper)[9][kLanes], unsigned m,
                           unsigned stored, CoarseDop* out) {
    // slabs s0 to s0 + 3 of `rows`: slab s of lane i at 8 (s - s0) + i
    auto narrow4 = [](const std::int32_t (*rows)[kLanes]) {
      const __m256i a = _mm512_cvtepi32_epi16(_mm512_loadu_si512(rows[0]));
      const __m256i b = _mm512_cvtepi32_epi16(_mm512_loadu_si512(rows[2]));
      return _mm512_inserti64x4(_mm512_castsi256_si512(a), b, 1);
    };
    const __m512i lo_a = narrow4(&lower[0]), lo_b = narrow4(&lower[4]);
    const __m512i hi_a = narrow4(&upper[0]), hi_b = narrow4(&upper[4]);
    // slab 8: the lower bound of lane i at i, its upper bound at 8 + i
    const __m512i last = _mm512_castsi256_si512(_mm512_cvtepi32_epi16(_mm512_inserti64x4(
        _mm512_castsi256_si512(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(lower[8]))),
        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(upper[8])), 1)));
    // Record entry j (lower bounds at 0-8, upper ones at 16-24) of lane 0: entries 0-7 and
    // 16-23 from the pairs of registers above (32 and on: the second of a pair), 8 and 24
    // from `last`; every lane's the same plus its index.
    alignas(64) static constexpr std::int16_t kFirst[32] = {0, 8,  16, 24, 32, 40, 48, 56, 0, 0, 0, 0, 0, 0, 0, 0,
                                                            0, 8,  16, 24, 32, 40, 48, 56, 8, 0, 0, 0, 0, 0, 0, 0};
    const __m512i first = _mm512_load_si512(kFirst);
    for (unsigned i = 0; i < m; ++i) {
      if (!(stored >> i & 1u)) continue;
      const __m512i at = _mm512_add_epi16(first, _mm512_set1_epi16(static_cast<short>(i)));
      const __m512i lo = _mm512_maskz_permutex2var_epi16(0x000000FFu, lo_a, at, lo_b);
      const __m512i hi = _mm512_maskz_permutex2var_epi16(0x00FF0000u, hi_a, at, hi_b);
      const __m512i mid = _mm512_maskz_permutexvar_epi16(0x01000100u, at, last);
      _mm512_store_si512(out + i, _mm512_or_si512(_mm512_or_si512(lo, hi), mid));
    }
  }
  /// A 4 x 8 transpose per 128-bit half: lane i's quarters in the low half of register i (i < 4)
  /// or the high half of register i - 4.
  static void store(const F (&lo)[4], const F (&hi)[4], unsigned m, unsigned stored, float* out) {
    F l[4], h[4];
    auto transpose = [](const F (&q)[4], F (&t)[4]) {
      const F a = _mm256_unpacklo_ps(q[0], q[1]), b = _mm256_unpackhi_ps(q[0], q[1]);
      const F c = _mm256_unpacklo_ps(q[2], q[3]), e = _mm256_unpackhi_ps(q[2], q[3]);
      t[0] = _mm256_shuffle_ps(a, c, _MM_SHUFFLE(1, 0, 1, 0));
      t[1] = _mm256_shuffle_ps(a, c, _MM_SHUFFLE(3, 2, 3, 2));
      t[2] = _mm256_shuffle_ps(b, e, _MM_SHUFFLE(1, 0, 1, 0));
      t[3] = _mm256_shuffle_ps(b, e, _MM_SHUFFLE(3, 2, 3, 2));
    };
    transpose(lo, l);
    transpose(hi, h);
    if (m == 8 && stored == 0xFFu) {  // every lane (most groups): stores without a branch
      for (unsigned i = 0; i < 4; ++i) {  // lane i's lower and upper bounds side by side: one store
        _mm256_store_ps(out + 72 * i, _mm256_permute2f128_ps(l[i], h[i], 0x20));
        _mm256_store_ps(out + 72 * (i + 4), _mm256_permute2f128_ps(l[i], h[i], 0x31));
      }
      return;
    }
    for (unsigned i = 0; i < m; ++i) {
      if (!(stored >> i & 1u)) continue;
      _mm_store_ps(out + 72 * i, i < 4 ? _mm256_castps256_ps128(l[i]) : _mm256_extractf128_ps(l[i - 4], 1));
      _mm_store_ps(out + 72 * i + 4, i < 4 ? _mm256_castps256_ps128(h[i]) : _mm256_extractf128_ps(h[i - 4], 1));
    }
  }
};
#include "vertex_quarters_kernel.inl"
constexpr decltype(LaneKernels::vertex_quarters) kVertexQuarters = &vertex_quarters;
/// LaneKernels::merge_quarters: a volume as four registers of two slabs (lower bounds, then
/// upper ones, of each) and one of the ninth, the lower lanes taking the minimum and the upper
/// ones the maximum, each with merge_each's operand order.
void merge_quarters(const float* base, const std::uint32_t* slots, std::size_t n, float* acc) {
  constexpr __mmask16 kLo = 0x0F0F, kHi = 0xF0F0, kLast = 0x00FF;
  __m512 a[5];
  for (int r = 0; r < 4; ++r) a[r] = _mm512_loadu_ps(acc + 16 * r);
  a[4] = _mm512_maskz_loadu_ps(kLast, acc + 64);
  for (std::size_t i = 0; i < n; ++i) {
    const float* q = base + 72 * std::size_t(slots ? slots[i] : i);
    for (int r = 0; r < 4; ++r) {
      const __m512 x = _mm512_loadu_ps(q + 16 * r);
      a[r] = _mm512_mask_min_ps(a[r], kLo, x, a[r]);
      a[r] = _mm512_mask_max_ps(a[r], kHi, x, a[r]);
    }
    const __m512 x = _mm512_maskz_loadu_ps(kLast, q + 64);
    a[4] = _mm512_mask_min_ps(a[4], kLo & kLast, x, a[4]);
    a[4] = _mm512_mask_max_ps(a[4], kHi & kLast, x, a[4]);
  }
  for (int r = 0; r < 4; ++r) _mm512_storeu_ps(acc + 16 * r, a[r]);
  _mm512_mask_storeu_ps(acc + 64, kLast, a[4]);
}
constexpr decltype(LaneKernels::merge_quarters) kMergeQuarters = &merge_quarters;
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
