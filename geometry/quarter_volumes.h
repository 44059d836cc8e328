#pragma once
/// @file Internal: the volumes of one feature over the four quarters [q/4, (q+1)/4] of a step,
/// as one value laid out for vector registers.
///
/// Layout (structure of arrays): for each slab of the k-DOP, the four quarters' lower bounds
/// side by side, then their upper bounds. Testing two features in all four quarters is then
/// one 4-lane comparison pair per slab (9 for the 18-DOP, 3 for the AABB), and merging two is
/// one min and one max per slab, with no shuffles:
///
///   lo(s)[q], hi(s)[q]: bounds along slab s (the axes of geometry/kdop.h) during quarter q.
///
/// A slab's bounds are next to each other, slab after slab: each slab's 32 bytes lie in one
/// cache line wherever the value starts on a 32-byte boundary (every element of an array: 288
/// bytes is 9 times 32).
///
/// Bounds are float, rounded outward by whoever fills them (SweptVolumes), like the k-DOPs.
#include <cstdint>
#include <limits>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define MCCD_WIDE_QUARTERS 1
#include <immintrin.h>
#endif

#include <mccd/geometry/kdop.h>

namespace mccd {

template <int Slabs>
struct alignas(32) QuarterDop {
  float bounds[Slabs][2][4];  ///< 32 * Slabs bytes: per slab, lo(s) then hi(s)

  /// The lower / upper bounds of quarters 0..3 along slab s (four floats).
  float* lo(int s) { return bounds[s][0]; }
  const float* lo(int s) const { return bounds[s][0]; }
  float* hi(int s) { return bounds[s][1]; }
  const float* hi(int s) const { return bounds[s][1]; }

  /// Empty in every quarter (overlaps nothing).
  static QuarterDop empty() {
    QuarterDop d;
    for (int s = 0; s < Slabs; ++s)
      for (int q = 0; q < 4; ++q) {
        d.lo(s)[q] = std::numeric_limits<float>::infinity();
        d.hi(s)[q] = -std::numeric_limits<float>::infinity();
      }
    return d;
  }

  /// Quarter q's volume becomes `d`.
  void set(int q, const Dop<Slabs>& d) {
    for (int s = 0; s < Slabs; ++s) {
      lo(s)[q] = d.lo[s];
      hi(s)[q] = d.hi[s];
    }
  }
  /// Quarter q's volume.
  Dop<Slabs> quarter(int q) const {
    Dop<Slabs> d;
    for (int s = 0; s < Slabs; ++s) {
      d.lo[s] = lo(s)[q];
      d.hi[s] = hi(s)[q];
    }
    return d;
  }
  /// The merge of the four quarters: a volume of the whole step containing every quarter's.
  Dop<Slabs> whole() const {
    Dop<Slabs> d;
    int s = 0;
#if defined(__SSE2__)
    // Four slabs at a time: transposed, lane i holds slab s + i, reduced in the loop's order.
    for (; s + 4 <= Slabs; s += 4) {
      __m128 l0 = _mm_load_ps(lo(s)), l1 = _mm_load_ps(lo(s + 1)), l2 = _mm_load_ps(lo(s + 2)),
             l3 = _mm_load_ps(lo(s + 3));
      __m128 h0 = _mm_load_ps(hi(s)), h1 = _mm_load_ps(hi(s + 1)), h2 = _mm_load_ps(hi(s + 2)),
             h3 = _mm_load_ps(hi(s + 3));
      _MM_TRANSPOSE4_PS(l0, l1, l2, l3);
      _MM_TRANSPOSE4_PS(h0, h1, h2, h3);
      _mm_storeu_ps(d.lo + s, _mm_min_ps(l3, _mm_min_ps(l2, _mm_min_ps(l1, l0))));
      _mm_storeu_ps(d.hi + s, _mm_max_ps(h3, _mm_max_ps(h2, _mm_max_ps(h1, h0))));
    }
#endif
    for (; s < Slabs; ++s) {
      float l = lo(s)[0], h = hi(s)[0];
      for (int q = 1; q < 4; ++q) {
        l = lo(s)[q] < l ? lo(s)[q] : l;
        h = hi(s)[q] > h ? hi(s)[q] : h;
      }
      d.lo[s] = l;
      d.hi[s] = h;
    }
    return d;
  }

  /// Grows every quarter to contain the same quarter of `o`.
  void merge(const QuarterDop& o) {
#if defined(__SSE2__)
    for (int s = 0; s < Slabs; ++s) {
      _mm_store_ps(lo(s), _mm_min_ps(_mm_load_ps(o.lo(s)), _mm_load_ps(lo(s))));
      _mm_store_ps(hi(s), _mm_max_ps(_mm_load_ps(o.hi(s)), _mm_load_ps(hi(s))));
    }
#else
    for (int s = 0; s < Slabs; ++s)
      for (int q = 0; q < 4; ++q) {
        lo(s)[q] = o.lo(s)[q] < lo(s)[q] ? o.lo(s)[q] : lo(s)[q];
        hi(s)[q] = o.hi(s)[q] > hi(s)[q] ? o.hi(s)[q] : hi(s)[q];
      }
#endif
  }
  /// Grows to contain at(0), ..., at(n - 1) (each a QuarterDop), merged in that order as
  /// merge() would: the lower bounds then the upper ones, each over all n, with the bounds
  /// held in registers (merge() reads and writes this volume's for each).
  template <class At>
  void merge_each(std::uint32_t n, const At& at) {
#if defined(__SSE2__)
    __m128 acc[Slabs];
    for (int s = 0; s < Slabs; ++s) acc[s] = _mm_load_ps(lo(s));
    for (std::uint32_t i = 0; i < n; ++i) {
      const QuarterDop& o = at(i);
      for (int s = 0; s < Slabs; ++s) acc[s] = _mm_min_ps(_mm_load_ps(o.lo(s)), acc[s]);
    }
    for (int s = 0; s < Slabs; ++s) _mm_store_ps(lo(s), acc[s]);
    for (int s = 0; s < Slabs; ++s) acc[s] = _mm_load_ps(hi(s));
    for (std::uint32_t i = 0; i < n; ++i) {
      const QuarterDop& o = at(i);
      for (int s = 0; s < Slabs; ++s) acc[s] = _mm_max_ps(_mm_load_ps(o.hi(s)), acc[s]);
    }
    for (int s = 0; s < Slabs; ++s) _mm_store_ps(hi(s), acc[s]);
#else
    for (std::uint32_t i = 0; i < n; ++i) merge(at(i));
#endif
  }
  /// Becomes the merge of `a` and `b`.
  void merge_of(const QuarterDop& a, const QuarterDop& b) {
#if defined(__SSE2__)
    for (int s = 0; s < Slabs; ++s) {
      _mm_store_ps(lo(s), _mm_min_ps(_mm_load_ps(b.lo(s)), _mm_load_ps(a.lo(s))));
      _mm_store_ps(hi(s), _mm_max_ps(_mm_load_ps(b.hi(s)), _mm_load_ps(a.hi(s))));
    }
#else
    *this = a;
    merge(b);
#endif
  }
  static QuarterDop merged(const QuarterDop& a, const QuarterDop& b) {
    QuarterDop d;
    d.merge_of(a, b);
    return d;
  }

  /// Bit q (0..3) set when the two volumes of quarter q overlap (touching counts), for the
  /// quarters of `within` only (the other bits are 0). A NaN bound never separates. Every slab
  /// is tested, without a branch: whether a pair is apart along the box slabs already is too
  /// hard to predict for a branch on it to pay.
  [[gnu::always_inline]] unsigned overlap_mask(const QuarterDop& o, unsigned within = 0xF) const {
#if defined(__SSE2__)
    __m128 sep = _mm_setzero_ps();
    for (int s = 0; s < Slabs; ++s)
      sep = _mm_or_ps(sep, _mm_or_ps(_mm_cmpgt_ps(_mm_load_ps(lo(s)), _mm_load_ps(o.hi(s))),
                                     _mm_cmpgt_ps(_mm_load_ps(o.lo(s)), _mm_load_ps(hi(s)))));
    return ~static_cast<unsigned>(_mm_movemask_ps(sep)) & within & 0xFu;
#else
    unsigned mask = 0;
    for (int q = 0; q < 4; ++q) {
      bool sep = false;
      for (int s = 0; s < Slabs; ++s) sep |= (lo(s)[q] > o.hi(s)[q]) | (o.lo(s)[q] > hi(s)[q]);
      mask |= static_cast<unsigned>(!sep) << q;
    }
    return mask & within;
#endif
  }
};

static_assert(sizeof(QuarterDop<9>) == 288, "18-DOP over four quarters: 72 floats");
static_assert(sizeof(QuarterDop<3>) == 96, "AABB over four quarters: 24 floats");

#if defined(MCCD_WIDE_QUARTERS)
/// The 18-DOP's quarter volumes in AVX-512 registers: four registers of two slabs each and a
/// half register for the ninth, lower and upper bounds side by side, so a test or a merge is a
/// few operations where SSE2 takes 18 of each. For the loops compiled for AVX-512 only (a
/// function with this attribute, or one that inlines every call, `flatten`), and only where the
/// processor has it (core/leaf_rule_pairs.h asks lane_kernels()). They give overlap_mask()'s,
/// merge()'s and merge_of()'s bits: the same comparisons and the same operand order of min and
/// max (the second operand where one is NaN or both are zeros).
#define MCCD_WIDE_TARGET __attribute__((target("avx512f,avx512vl,avx512bw,avx512dq")))
/// Every lane (the masked forms: GCC 12's unmasked ones read an undefined register that it then
/// warns about when inlined, its bug 105593).
inline constexpr __mmask16 kWideLanes = 0xFFFF;

/// `a` with each slab's lower and upper bounds exchanged (for wide_overlap_mask()).
MCCD_WIDE_TARGET inline void wide_swapped(const QuarterDop<9>& a, QuarterDop<9>& out) {
  const float* x = a.bounds[0][0];
  float* y = out.bounds[0][0];
  for (int r = 0; r < 4; ++r) {
    const __m512 v = _mm512_loadu_ps(x + 16 * r);
    _mm512_storeu_ps(y + 16 * r, _mm512_maskz_shuffle_f32x4(kWideLanes, v, v, _MM_SHUFFLE(2, 3, 0, 1)));
  }
  const __m256 t = _mm256_loadu_ps(x + 64);
  _mm256_storeu_ps(y + 64, _mm256_shuffle_f32x4(t, t, 1));
}
/// a.overlap_mask(b, within), given `swapped` = wide_swapped(a).
MCCD_WIDE_TARGET inline unsigned wide_overlap_mask(const QuarterDop<9>& swapped, const QuarterDop<9>& b,
                                                   unsigned within = 0xF) {
  const float* x = swapped.bounds[0][0];
  const float* y = b.bounds[0][0];
  // lanes 0-3 and 8-11 of a register: b's lower bound above a's upper one; lanes 4-7 and
  // 12-15: a's lower bound above b's upper one (ordered comparisons: false with a NaN)
  __mmask16 apart = 0;
  for (int r = 0; r < 4; ++r) {
    const __m512 u = _mm512_loadu_ps(x + 16 * r), v = _mm512_loadu_ps(y + 16 * r);
    apart |= _mm512_mask_cmp_ps_mask(0x0F0F, u, v, _CMP_LT_OQ) | _mm512_mask_cmp_ps_mask(0xF0F0, u, v, _CMP_GT_OQ);
  }
  const __m256 u = _mm256_loadu_ps(x + 64), v = _mm256_loadu_ps(y + 64);
  const unsigned last =
      _mm256_mask_cmp_ps_mask(0x0F, u, v, _CMP_LT_OQ) | _mm256_mask_cmp_ps_mask(0xF0, u, v, _CMP_GT_OQ);
  unsigned m = apart | last;  // bit 4 k + q: quarter q apart along some slab
  m |= m >> 8;
  m |= m >> 4;
  return ~m & within & 0xFu;
}
/// out.merge_of(a, b).
MCCD_WIDE_TARGET inline void wide_merge_of(QuarterDop<9>& out, const QuarterDop<9>& a, const QuarterDop<9>& b) {
  const float* x = a.bounds[0][0];
  const float* y = b.bounds[0][0];
  float* z = out.bounds[0][0];
  for (int r = 0; r < 4; ++r) {
    const __m512 u = _mm512_loadu_ps(x + 16 * r), v = _mm512_loadu_ps(y + 16 * r);
    _mm512_storeu_ps(z + 16 * r, _mm512_mask_max_ps(_mm512_maskz_min_ps(kWideLanes, v, u), 0xF0F0, v, u));
  }
  const __m256 u = _mm256_loadu_ps(x + 64), v = _mm256_loadu_ps(y + 64);
  _mm256_storeu_ps(z + 64, _mm256_mask_max_ps(_mm256_min_ps(v, u), 0xF0, v, u));
}
/// out.merge(o).
MCCD_WIDE_TARGET inline void wide_merge(QuarterDop<9>& out, const QuarterDop<9>& o) { wide_merge_of(out, out, o); }
#endif

/// How far a vertex's quarter volumes (SweptVolumes::vertex_volumes and the vector kernels,
/// LaneKernels::vertex_quarters) lie outside its path. Along each slab, quarter q's lower bound
/// is y = min(p_q, p_q+1) - m rounded to float (the upper one: max + m), where p_k is the
/// vertex's projection at t = k/4 computed in double and m = quarter_margin(M, d), M the largest
/// coordinate of its two positions, d the minimum distance. Why the bound holds the exact path
/// moved out by d:
///  - each p_k is off the exact projection of the exact point by at most 13 units of 2^-53 M
///    (the ends' projections, their difference, the product and the sum), and |p_k| <= 2M;
///  - the subtraction rounds by at most 2^-53 |y|, and the float conversion by at most 2^-24 |y|
///    (2^-23 in any rounding mode) where |y| is at least the least normal float, by less than
///    2^-126 below that, also where a host's flush-to-zero makes the float 0;
///  - with |y| <= 2M + m, those sum to under half of m - d (under m - d in any rounding mode).
/// The products by powers of two are exact (short of denormal doubles), so the operations give
/// the same bits with or without fused multiply-adds. Past the float range (rounding to
/// nearest: the other modes round there to the largest float) a lower bound that rounds to +inf
/// becomes the largest float, still below y, and an upper bound that rounds to -inf its
/// negative; with M at most kQuarterNoClamp no bound rounds there (|p_k| is at most a hair over
/// 2^127), so a caller may skip that.
inline constexpr double kQuarterRelative = 0x1p-21;
inline constexpr double kQuarterLeast = 0x1p-124;
inline constexpr double kQuarterNoClamp = 0x1p126;
inline double quarter_margin(double largest, double distance) {
  return (largest * kQuarterRelative + (distance + distance * kQuarterRelative)) + kQuarterLeast;
}

/// The quarter volumes that go with a bounding volume type.
template <class BV>
using QuarterVolume = QuarterDop<BV::kSlabs>;

}  // namespace mccd
