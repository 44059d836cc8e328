// Quarter volumes (geometry/quarter_volumes.h) and the swept volumes of a step
// (geometry/swept_volumes.h): the vector test equals the per-quarter definition, and every
// volume contains the exact path of its feature over its quarter, including at extreme
// coordinates, so no contact can be culled.
#include <gtest/gtest.h>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <mccd/geometry/coarse_volumes.h>
#include <mccd/geometry/quarter_volumes.h>
#include <mccd/geometry/swept_volumes.h>

#include "support/simd_levels.h"

using namespace mccd;
using namespace mccd::detail;

namespace {

/// Whether the exact point p (long double) lies in `d` along every slab, with projections
/// computed in long double (exact for the inputs used: a few sums of doubles).
template <int S>
bool contains_exactly(const Dop<S>& d, const long double p[3]) {
  const long double pr[9] = {p[0],        p[1],        p[2],        p[0] + p[1], p[0] - p[1],
                             p[0] + p[2], p[0] - p[2], p[1] + p[2], p[1] - p[2]};
  for (int s = 0; s < S; ++s)
    if (pr[s] < d.lo[s] || pr[s] > d.hi[s]) return false;
  return true;
}

template <int S>
QuarterDop<S> random_quarters(std::mt19937& rng) {
  std::uniform_int_distribution<int> pick(-3, 3);
  QuarterDop<S> q;
  for (int s = 0; s < S; ++s)
    for (int k = 0; k < 4; ++k) {
      const float a = static_cast<float>(pick(rng)), b = static_cast<float>(pick(rng));
      q.lo(s)[k] = std::min(a, b);
      q.hi(s)[k] = std::max(a, b);
    }
  return q;
}

}  // namespace

#if defined(MCCD_WIDE_QUARTERS)
// The AVX-512 forms of the test and the merges (the leaf pairs' loops at that level) give the
// SSE2 forms' bits, with NaN bounds, zeros of either sign, infinities and unordered bounds.
TEST(QuarterVolumes, WideTestAndMergesGiveTheSameBits) {
  if (!__builtin_cpu_supports("avx512f") || !__builtin_cpu_supports("avx512bw") ||
      !__builtin_cpu_supports("avx512vl") || !__builtin_cpu_supports("avx512dq"))
    GTEST_SKIP() << "this processor has no AVX-512 (F, BW, VL, DQ): the wide forms never run here";
  std::mt19937 rng(11);
  const float inf = std::numeric_limits<float>::infinity();
  const float values[] = {-3, -2, -1, -0.0f, 0.0f, 1, 2, 3, inf, -inf, std::nanf("")};
  auto any = [&] {
    QuarterDop<9> q;
    for (int s = 0; s < 9; ++s)
      for (int k = 0; k < 4; ++k) {
        q.lo(s)[k] = values[rng() % 11];
        q.hi(s)[k] = values[rng() % 11];
      }
    return q;
  };
  for (int i = 0; i < 20000; ++i) {
    // mostly ordered bounds (so that some quarters overlap), some not
    const QuarterDop<9> a = i % 4 ? random_quarters<9>(rng) : any(), b = i % 3 ? random_quarters<9>(rng) : any();
    const unsigned within = static_cast<unsigned>(rng() % 16);
    QuarterDop<9> swapped;
    wide_swapped(a, swapped);
    ASSERT_EQ(wide_overlap_mask(swapped, b, within), a.overlap_mask(b, within)) << i;
    QuarterDop<9> narrow, wide;
    narrow.merge_of(a, b);
    wide_merge_of(wide, a, b);
    ASSERT_EQ(std::memcmp(&narrow, &wide, sizeof narrow), 0) << i;
    narrow = a;
    narrow.merge(b);
    wide = a;
    wide_merge(wide, b);
    ASSERT_EQ(std::memcmp(&narrow, &wide, sizeof narrow), 0) << i;
  }
}
#endif

TEST(QuarterVolumes, MaskMergeAndWholeEqualThePerQuarterDefinitions) {
  std::mt19937 rng(3);
  for (int i = 0; i < 2000; ++i) {
    const QuarterDop<9> a = random_quarters<9>(rng), b = random_quarters<9>(rng);
    const unsigned within = static_cast<unsigned>(rng() % 16);
    unsigned expect = 0;
    for (int q = 0; q < 4; ++q)
      if ((within >> q & 1u) && a.quarter(q).overlaps(b.quarter(q))) expect |= 1u << q;
    ASSERT_EQ(a.overlap_mask(b, within), expect);
    ASSERT_EQ(b.overlap_mask(a, within), expect);
    // A NaN bound never separates: it counts as an infinite one.
    QuarterDop<9> n = a;
    const int s = static_cast<int>(rng() % 9), q = static_cast<int>(rng() % 4);
    const bool lower = rng() % 2;
    (lower ? n.lo(s) : n.hi(s))[q] = std::nanf("");
    Kdop18 nq = a.quarter(q);
    const float inf = std::numeric_limits<float>::infinity();
    (lower ? nq.lo : nq.hi)[s] = lower ? -inf : inf;
    const Kdop18 bq = b.quarter(q);
    const unsigned with_nan = (expect & ~(1u << q)) | static_cast<unsigned>((within >> q & 1u) && nq.overlaps(bq)) << q;
    ASSERT_EQ(n.overlap_mask(b, within), with_nan) << i;
    ASSERT_EQ(b.overlap_mask(n, within), with_nan) << i;
    const QuarterDop<9> m = QuarterDop<9>::merged(a, b);
    Kdop18 whole = Kdop18::empty();
    for (int q = 0; q < 4; ++q) {
      const Kdop18 e = Kdop18::merged(a.quarter(q), b.quarter(q));
      for (int s = 0; s < 9; ++s) {
        ASSERT_EQ(m.lo(s)[q], e.lo[s]);
        ASSERT_EQ(m.hi(s)[q], e.hi[s]);
      }
      whole.merge(a.quarter(q));
    }
    const Kdop18 w = a.whole();
    for (int s = 0; s < 9; ++s) {
      ASSERT_EQ(w.lo[s], whole.lo[s]);
      ASSERT_EQ(w.hi[s], whole.hi[s]);
    }
  }
  // The box variant too.
  const QuarterDop<3> a = random_quarters<3>(rng), b = random_quarters<3>(rng);
  unsigned expect = 0;
  for (int q = 0; q < 4; ++q) expect |= static_cast<unsigned>(a.quarter(q).overlaps(b.quarter(q))) << q;
  EXPECT_EQ(a.overlap_mask(b), expect);
  EXPECT_EQ(QuarterDop<9>::empty().overlap_mask(QuarterDop<9>::empty()), 0u);
}

TEST(QuarterVolumes, MergeEachIsOneMergeAfterAnother) {
  // merge_each (the bounds held in registers) against merge() item by item, bit for bit,
  // including NaN bounds (whose outcome depends on the operands' order) and empty lists.
  std::mt19937 rng(8);
  for (int i = 0; i < 500; ++i) {
    std::vector<QuarterDop<9>> items;
    const int n = static_cast<int>(rng() % 24);
    for (int k = 0; k < n; ++k) {
      items.push_back(random_quarters<9>(rng));
      if (rng() % 16 == 0) items.back().lo(static_cast<int>(rng() % 9))[rng() % 4] = std::nanf("");
      if (rng() % 16 == 0) items.back().hi(static_cast<int>(rng() % 9))[rng() % 4] = std::nanf("");
    }
    QuarterDop<9> one = i % 3 ? random_quarters<9>(rng) : QuarterDop<9>::empty(), each = one;
    for (const auto& q : items) one.merge(q);
    each.merge_each(static_cast<std::uint32_t>(items.size()),
                    [&](std::uint32_t k) -> const QuarterDop<9>& { return items[k]; });
    ASSERT_EQ(std::memcmp(&one, &each, sizeof one), 0) << i;
  }
}

TEST(QuarterVolumes, MergeQuartersInLanesIsMergeEachAtEveryLevel) {
  // LaneKernels::merge_quarters (where a level has it) against merge_each, bit for bit: from a
  // run of volumes and through a list of slots, NaN and infinite bounds included, empty lists.
  std::mt19937 rng(9);
  std::vector<QuarterDop<9>> items(64);
  for (auto& q : items) {
    q = random_quarters<9>(rng);
    if (rng() % 8 == 0) q.lo(static_cast<int>(rng() % 9))[rng() % 4] = std::nanf("");
    if (rng() % 8 == 0) q.hi(static_cast<int>(rng() % 9))[rng() % 4] = std::nanf("");
    if (rng() % 8 == 0) q.hi(8)[rng() % 4] = std::numeric_limits<float>::infinity();
  }
  const auto* base = reinterpret_cast<const float*>(items.data());
  bool any = false;
  for (SimdLevel level : {SimdLevel::Scalar, SimdLevel::Sse2, SimdLevel::Avx2, SimdLevel::Avx512}) {
    const LaneKernels* k = lane_kernels_for(level);
    if (!k || !k->merge_quarters) continue;
    any = true;
    for (int i = 0; i < 300; ++i) {
      const std::size_t first = rng() % 40, n = rng() % 24;
      std::vector<std::uint32_t> slots(rng() % 24);
      for (auto& s : slots) s = static_cast<std::uint32_t>(rng() % items.size());
      QuarterDop<9> each = i % 3 ? random_quarters<9>(rng) : QuarterDop<9>::empty(), lanes = each;
      each.merge_each(static_cast<std::uint32_t>(n),
                      [&](std::uint32_t j) -> const QuarterDop<9>& { return items[first + j]; });
      each.merge_each(static_cast<std::uint32_t>(slots.size()),
                      [&](std::uint32_t j) -> const QuarterDop<9>& { return items[slots[j]]; });
      k->merge_quarters(base + 72 * first, nullptr, n, lanes.bounds[0][0]);
      k->merge_quarters(base, slots.data(), slots.size(), lanes.bounds[0][0]);
      ASSERT_EQ(std::memcmp(&each, &lanes, sizeof each), 0) << to_string(level) << " " << i;
    }
  }
  if (!any) GTEST_SKIP() << "no SIMD level of this processor has merge_quarters (AVX-512 only)";
}

template <class BV>
void check_paths_are_contained(double scale, double min_distance) {
  // Two triangles sharing an edge, moving on random segments; every vertex's exact position at
  // many times of each quarter lies in that quarter's volume of the vertex, of its edges and of
  // its faces, and in the whole-step volumes.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(-1, 1);
  const std::vector<Triangle> faces = {{0, 1, 2}, {1, 3, 2}};
  const MeshTopology topo(4, faces);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<double> x0(12), x1(12);
    for (int i = 0; i < 12; ++i) {
      x0[i] = scale * U(rng);
      x1[i] = trial % 7 == 0 ? x0[i] : scale * U(rng);  // some still
    }
    SweptVolumes<BV> sw;
    sw.resize(topo);
    sw.update_vertices(x0.data(), x1.data(), min_distance, 0, 4);  // edges and faces: merged on demand
    for (int q = 0; q < 4; ++q)
      for (int j = 0; j <= 16; ++j) {
        const long double t = (q + j / 16.0L) / 4;  // exact dyadic times across the quarter
        for (std::uint32_t v = 0; v < 4; ++v) {
          long double p[3];
          for (int k = 0; k < 3; ++k) p[k] = x0[3 * v + k] + t * ((long double)x1[3 * v + k] - x0[3 * v + k]);
          ASSERT_TRUE(contains_exactly(sw.vertex_quarters(v).quarter(q), p)) << "vertex " << v << " t " << (double)t;
          ASSERT_TRUE(contains_exactly(sw.vertex(v), p));
          for (std::uint32_t f = 0; f < 2; ++f) {
            if (faces[f][0] == v || faces[f][1] == v || faces[f][2] == v) {
              ASSERT_TRUE(contains_exactly(sw.face_quarters(faces[f]).quarter(q), p));
              ASSERT_TRUE(contains_exactly(sw.face(f), p));
            }
          }
          for (std::uint32_t e = 0; e < topo.num_edges(); ++e) {
            if (topo.edges()[e][0] == v || topo.edges()[e][1] == v) {
              ASSERT_TRUE(contains_exactly(sw.edge_quarters(e).quarter(q), p));
            }
          }
        }
      }
  }
}

TEST(SweptVolumes, QuarterVolumesContainTheExactPaths) {
  for (double scale : {1.0, 1e-30, 1e6, 1e30}) {
    SCOPED_TRACE(scale);
    check_paths_are_contained<Kdop18>(scale, 0.0);
    check_paths_are_contained<Aabb>(scale, 0.0);
  }
  check_paths_are_contained<Kdop18>(1.0, 0.01);
}

TEST(SweptVolumes, VertexQuartersHoldTheExactPathsInEveryModeAndLevel) {
  // Every level's vertex volumes (the vector kernels where a level has them) contain the exact
  // path of each vertex over each quarter, moved out by the minimum distance, and lie within
  // 2^-19 of the largest coordinate (four times quarter_margin's) plus float rounding of it:
  // rounding to nearest, also with flush-to-zero and denormals-are-zero (as a host built with
  // -ffast-math runs), from denormal coordinates to beyond float range; rounding towards either
  // infinity or zero, within float range (past it, those modes round to the largest float).
  const std::size_t n = 203;
  const MeshTopology topo(n, {});
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> unit(-1, 1);
  const test::KeepSimdLevel restore_level;
#if defined(__SSE2__)
  struct Restore {
    unsigned csr = _mm_getcsr();
    ~Restore() { _mm_setcsr(csr); }
  } restore_csr;
  constexpr unsigned kDaz = 0x0040u;  // denormals are zero
  const unsigned base = restore_csr.csr & ~(_MM_ROUND_MASK | _MM_FLUSH_ZERO_MASK | kDaz);
  const unsigned directed = _MM_ROUND_MASK;  // the rounding-mode bits (nearest: none set)
  const std::pair<unsigned, const char*> modes[] = {{_MM_ROUND_NEAREST, "nearest"},
                                                    {_MM_ROUND_UP, "up"},
                                                    {_MM_ROUND_DOWN, "down"},
                                                    {_MM_ROUND_TOWARD_ZERO, "toward zero"},
                                                    {_MM_ROUND_NEAREST | _MM_FLUSH_ZERO_ON | kDaz, "flush to zero"}};
#else
  const unsigned directed = 0u;
  const std::pair<unsigned, const char*> modes[] = {{0u, "default"}};
#endif
  for (double scale : {1.0, 1e-30, 1e-38, 1e-41, 1e-45, 1e6, 1e30, 1e38, 3e38, 1e300})
    for (double distance : {0.0, 1e-3 * scale}) {
      std::vector<double> x0(3 * n), x1(3 * n);
      for (std::size_t i = 0; i < 3 * n; ++i) {
        x0[i] = scale * unit(rng);
        x1[i] = i % 7 == 0 ? x0[i] : scale * unit(rng);  // some still
      }
      for (auto [mode, mode_name] : modes) {
        if ((mode & directed) != 0 && scale > 1e38) continue;
        for (const LaneKernels* kernels : test::available_levels()) {
          SCOPED_TRACE(std::string(mode_name) + ", " + to_string(kernels->level) + ", scale " + std::to_string(scale) +
                       ", distance " + std::to_string(distance));
          select_simd_level(kernels->level);
          SweptVolumes<Kdop18> sw;
          sw.resize(topo);
#if defined(__SSE2__)
          _mm_setcsr(base | mode);
#else
          (void)mode;
#endif
          sw.update_vertex_slots(x0.data(), x1.data(), distance, 0, n);
#if defined(__SSE2__)
          _mm_setcsr(restore_csr.csr);
#endif
          for (std::uint32_t v = 0; v < n; ++v) {
            long double largest = 0;
            for (int k = 0; k < 3; ++k)
              largest = std::max({largest, std::fabs((long double)x0[3 * v + k]),
                                  std::fabs((long double)x1[3 * v + k])});
            const long double loose = largest * 0x1p-19L + distance * (1 + 0x1p-19L) + 0x1p-122L;
            const QuarterDop<9>& q = sw.vertex_quarters(v);
            for (int quarter = 0; quarter < 4; ++quarter) {
              // the exact projections at the quarter's ends (a line: its extremes are there)
              long double pr[2][9];
              for (int e = 0; e < 2; ++e) {
                const long double t = (quarter + e) / 4.0L;
                long double p[3];
                for (int k = 0; k < 3; ++k) p[k] = x0[3 * v + k] + t * ((long double)x1[3 * v + k] - x0[3 * v + k]);
                const long double all[9] = {p[0],        p[1],        p[2],        p[0] + p[1], p[0] - p[1],
                                            p[0] + p[2], p[0] - p[2], p[1] + p[2], p[1] - p[2]};
                std::copy(all, all + 9, pr[e]);
              }
              for (int s = 0; s < 9; ++s) {
                const long double lo = std::min(pr[0][s], pr[1][s]) - distance;
                const long double hi = std::max(pr[0][s], pr[1][s]) + distance;
                const long double got_lo = q.lo(s)[quarter], got_hi = q.hi(s)[quarter];
                ASSERT_LE(got_lo, lo) << "vertex " << v << ", quarter " << quarter << ", slab " << s;
                ASSERT_GE(got_hi, hi) << "vertex " << v << ", quarter " << quarter << ", slab " << s;
                if (scale < 1e38) {  // (past float range a bound is the largest float or infinite)
                  ASSERT_LE(lo - got_lo, loose - distance + 0x1p-22L * std::fabs(got_lo)) << "vertex " << v;
                  ASSERT_LE(got_hi - hi, loose - distance + 0x1p-22L * std::fabs(got_hi)) << "vertex " << v;
                }
              }
            }
          }
        }
      }
    }
}

TEST(SweptVolumes, LayoutMovesStorageNotValues) {
  // The same volumes by id whatever the storage layout.
  const std::vector<Triangle> faces = {{0, 1, 2}, {1, 3, 2}, {2, 3, 4}};
  const MeshTopology topo(5, faces);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<double> x0(15), x1(15);
  for (int i = 0; i < 15; ++i) x0[i] = U(rng), x1[i] = U(rng);
  VolumeLayout layout;
  layout.vertex_slot = {4, 2, 0, 1, 3};
  layout.face_slot = {2, 0, 1};
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e)
    layout.edge_slot.push_back(static_cast<std::uint32_t>(topo.num_edges() - 1 - e));
  SweptVolumes<Kdop18> a, b, c;
  a.resize(topo);
  b.resize(topo, layout);
  c.resize(topo, layout);
  for (SweptVolumes<Kdop18>* s : {&a, &b}) s->update_vertices(x0.data(), x1.data(), 0.0, 0, 5);
  // The storage-order update (every vertex moving), in two slot ranges.
  c.update_vertex_slots(x0.data(), x1.data(), 0.0, 0, 2);
  c.update_vertex_slots(x0.data(), x1.data(), 0.0, 2, 5);
  auto same = [](const auto& x, const auto& y) { return std::memcmp(&x, &y, sizeof(x)) == 0; };
  for (std::uint32_t v = 0; v < 5; ++v) {
    EXPECT_TRUE(same(a.vertex_quarters(v), b.vertex_quarters(v)));
    EXPECT_TRUE(same(b.vertex_quarters(v), b.vertex_quarters_at(layout.vertex_slot[v])));
    EXPECT_TRUE(same(b.vertex_quarters(v), c.vertex_quarters(v)));
    EXPECT_TRUE(same(b.vertex(v), c.vertex(v)));
  }
  for (std::uint32_t f = 0; f < 3; ++f) {
    EXPECT_TRUE(same(a.face(f), b.face(f)));
    EXPECT_TRUE(same(b.face(f), c.face(f)));
    EXPECT_TRUE(same(b.face(f), b.face_at(layout.face_slot[f])));
  }
  for (std::uint32_t e = 0; e < topo.num_edges(); ++e) {
    EXPECT_TRUE(same(a.edge_quarters(e), b.edge_quarters(e)));
    EXPECT_TRUE(same(b.edge_quarters(e), b.edge_quarters_at(layout.edge_slot[e])));
    EXPECT_TRUE(same(b.edge_quarters(e), c.edge_quarters(e)));
  }
}

TEST(SweptVolumes, SlotUpdateVisitsEverySlotOnceWithItsStoredQuarters) {
  // update_vertex_slots' visitor (the update's second consumer, the leaf lanes) sees each slot
  // of its range once, updated or kept, with the quarters as stored; the whole-step volumes
  // read back are the merges of those quarters, slab by slab.
  const std::vector<Triangle> faces = {{0, 1, 2}, {1, 3, 2}, {2, 3, 4}};
  const MeshTopology topo(5, faces);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(-2, 2);
  std::vector<double> x0(15), x1(15), y1(15);
  for (int i = 0; i < 15; ++i) x0[i] = U(rng), x1[i] = U(rng), y1[i] = U(rng);
  VolumeLayout layout;
  layout.vertex_slot = {3, 0, 4, 1, 2};
  layout.face_slot = {1, 2, 0};
  SweptVolumes<Kdop18> s;
  s.resize(topo, layout);
  s.update_vertex_slots(x0.data(), x1.data(), 0.0, 0, 5);
  // a second step in which vertex 2 (slot 4) is kept: its volumes stay those of x0 -> x1
  const std::uint8_t kept[5] = {0, 0, 1, 0, 0};
  std::vector<int> seen(5, 0);
  s.update_vertex_slots(x0.data(), y1.data(), 0.0, 1, 5, kept, [&](std::size_t slot, const auto& q) {
    ++seen[slot];
    EXPECT_EQ(&q, &s.vertex_quarters_at(static_cast<std::uint32_t>(slot)));
  });
  EXPECT_EQ(seen, (std::vector<int>{0, 1, 1, 1, 1}));
  SweptVolumes<Kdop18> fresh;
  fresh.resize(topo, layout);
  fresh.update_vertices(x0.data(), x1.data(), 0.0, 0, 5);
  auto same = [](const auto& x, const auto& y) { return std::memcmp(&x, &y, sizeof(x)) == 0; };
  EXPECT_TRUE(same(s.vertex_quarters(2), fresh.vertex_quarters(2))) << "a kept vertex was updated";
  EXPECT_FALSE(same(s.vertex_quarters(0), fresh.vertex_quarters(0))) << "a moved vertex kept its volumes";
  for (std::uint32_t v = 0; v < 5; ++v) {
    const auto& q = s.vertex_quarters(v);
    const Kdop18 whole = s.vertex(v);
    for (int k = 0; k < Kdop18::kSlabs; ++k) {
      EXPECT_EQ(whole.lo[k], std::min({q.lo(k)[0], q.lo(k)[1], q.lo(k)[2], q.lo(k)[3]})) << "vertex " << v;
      EXPECT_EQ(whole.hi[k], std::max({q.hi(k)[0], q.hi(k)[1], q.hi(k)[2], q.hi(k)[3]})) << "vertex " << v;
    }
  }
  for (std::uint32_t f = 0; f < 3; ++f) {
    Kdop18 merged = s.vertex(faces[f][0]);
    merged.merge(s.vertex(faces[f][1]));
    merged.merge(s.vertex(faces[f][2]));
    EXPECT_TRUE(same(s.face(f), merged)) << "face " << f;
  }
}

TEST(SweptVolumes, VertexQuartersBitForBitAtEverySimdLevel) {
  // The update's vertex volumes in vector lanes (LaneKernels::vertex_quarters, where a level has
  // them) equal the scalar code's bit for bit: over a permuted layout, a range that neither
  // starts nor ends on a register or a 64-slot group, kept slots (whole registers too) left as
  // they were, or none kept (whole registers written at once), and coordinates from 0 and
  // denormals to beyond float range.
  const std::size_t n = 203;
  const MeshTopology topo(n, {});
  std::mt19937 rng(17);
  std::vector<double> x0(3 * n), x1(3 * n), y1(3 * n);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> exponent(-60, 60), kind(0, 9);
  for (std::size_t i = 0; i < 3 * n; ++i) {
    const double scale = std::ldexp(1.0, exponent(rng));
    x0[i] = unit(rng) * scale;
    x1[i] = x0[i] + unit(rng) * scale * 0.01;
    y1[i] = unit(rng) * scale;
    switch (kind(rng)) {
      case 0: x0[i] = x1[i] = 0.0; break;                       // still at the origin
      case 1: x1[i] = x0[i]; break;                             // not moving
      case 2: x0[i] = -0.0, x1[i] = 4.9e-324; break;            // signed zero to a denormal
      case 3: x0[i] = 3e38 * unit(rng), x1[i] = -4e38; break;   // past float range
      default: break;
    }
  }
  VolumeLayout layout;
  layout.vertex_slot.resize(n);
  for (std::uint32_t v = 0; v < n; ++v) layout.vertex_slot[v] = v;
  std::shuffle(layout.vertex_slot.begin(), layout.vertex_slot.end(), rng);
  const test::KeepSimdLevel restore;
  auto run = [&](SimdLevel level, double distance, bool keep_some) {
    select_simd_level(level);
    SweptVolumes<Kdop18> s;
    s.resize(topo, layout);
    s.update_vertex_slots(x0.data(), y1.data(), 0.0, 0, n);  // what kept slots keep
    std::vector<int> seen(n, 0);
    s.update_vertex_slots_keeping(
        x0.data(), x1.data(), distance, 5, n - 3,
        [keep_some](std::uint32_t v, std::size_t slot) {
          return keep_some && ((v + slot) % 5 == 1 || (slot >= 40 && slot < 56));
        },
        [&](std::size_t slot, const auto& q) {
          ++seen[slot];
          EXPECT_EQ(&q, &s.vertex_quarters_at(static_cast<std::uint32_t>(slot)));
        });
    for (std::size_t slot = 0; slot < n; ++slot) EXPECT_EQ(seen[slot], slot >= 5 && slot < n - 3 ? 1 : 0);
    std::vector<QuarterDop<9>> out(n);
    for (std::uint32_t slot = 0; slot < n; ++slot) out[slot] = s.vertex_quarters_at(slot);
    return out;
  };
  for (bool keep_some : {true, false})
    for (double distance : {0.0, 1e-3}) {
      const std::vector<QuarterDop<9>> scalar = run(SimdLevel::Scalar, distance, keep_some);
      for (SimdLevel level : {SimdLevel::Sse2, SimdLevel::Avx2, SimdLevel::Avx512}) {
        if (!lane_kernels_for(level)) continue;
        const std::vector<QuarterDop<9>> got = run(level, distance, keep_some);
        for (std::size_t slot = 0; slot < n; ++slot)
          EXPECT_EQ(std::memcmp(&got[slot], &scalar[slot], sizeof(QuarterDop<9>)), 0)
              << to_string(level) << ", slot " << slot << ", distance " << distance << ", some kept " << keep_some;
      }
    }
}

TEST(SweptVolumes, VertexCoarseVolumesBitForBitWithTheirQuarters) {
  // With a coarse target, the vector kernel writes the coarse volumes of the slots it updates
  // (CoarseGrid::quantize of their quarters' merge, bit for bit) and leaves the kept slots to
  // the visitor; without the kernel, the visitor sees every slot.
  const std::size_t n = 150;
  const MeshTopology topo(n, {});
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> pos(-3, 3), step(-0.05, 0.05);
  std::vector<double> x0(3 * n), x1(3 * n);
  for (std::size_t i = 0; i < 3 * n; ++i) x0[i] = pos(rng), x1[i] = x0[i] + step(rng);
  x0[7] = std::numeric_limits<double>::max() / 4;  // clamped to the grid's end
  VolumeLayout layout;
  layout.vertex_slot.resize(n);
  for (std::uint32_t v = 0; v < n; ++v) layout.vertex_slot[v] = (v * 37) % n;
  Kdop18 box = Kdop18::empty();
  for (double c : {-2.0, 2.5}) box.add_point(Vec3(c, c * 0.5, -c));  // smaller than the points: some clamp
  const CoarseGrid<9> grid = CoarseGrid<9>::over(box);
  auto kept_slot = [](std::size_t slot) { return slot % 11 == 4; };
  const test::KeepSimdLevel restore;
  for (SimdLevel level : {SimdLevel::Sse2, SimdLevel::Avx2, SimdLevel::Avx512}) {
    if (!lane_kernels_for(level)) continue;
    select_simd_level(level);
    SweptVolumes<Kdop18> s;
    s.resize(topo, layout);
    std::vector<CoarseDop> coarse(n);
    for (CoarseDop& c : coarse) std::fill(std::begin(c.lo), std::end(c.lo), std::int16_t(7)), c.hi[0] = 7;
    std::vector<int> visited(n, 0);
    const CoarseOut out{grid.origin, grid.scale, coarse.data()};
    s.update_vertex_slots_keeping(
        x0.data(), x1.data(), 0.0, 0, n, [&](std::uint32_t, std::size_t slot) { return kept_slot(slot); },
        [&](std::size_t slot, const auto&) { ++visited[slot]; }, &out);
    const bool kernel = lane_kernels().vertex_quarters != nullptr;
    for (std::size_t slot = 0; slot < n; ++slot) {
      if (kept_slot(slot) || !kernel) {
        EXPECT_EQ(visited[slot], 1) << to_string(level) << ", slot " << slot;
        EXPECT_EQ(coarse[slot].lo[0], 7) << "the kernel wrote slot " << slot;
        continue;
      }
      EXPECT_EQ(visited[slot], 0) << to_string(level) << ", slot " << slot;
      std::int16_t want[18];
      grid.quantize(s.vertex_quarters_at(static_cast<std::uint32_t>(slot)).whole(), want);
      for (int k = 0; k < 16; ++k) {
        EXPECT_EQ(coarse[slot].lo[k], k < 9 ? want[k] : 0) << "slot " << slot << ", bound " << k;
        EXPECT_EQ(coarse[slot].hi[k], k < 9 ? want[9 + k] : 0) << "slot " << slot << ", bound " << k;
      }
    }
  }
}
