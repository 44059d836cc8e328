// The lane kernels (geometry/lane_masks.h) at every instruction set this processor has, against
// plain references; and the coarse volumes they test (geometry/coarse_volumes.h).
#include <mccd/geometry/ccd.h>
#include <mccd/geometry/ccd_detail.h>
#include <mccd/geometry/ccd_filter.h>
#include <mccd/geometry/coarse_volumes.h>
#include <mccd/geometry/error.h>
#include <mccd/geometry/kdop.h>
#include <mccd/geometry/lane_masks.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "support/simd_levels.h"

using namespace mccd;
using namespace mccd::detail;

namespace {

/// Plain references on coarse volumes as `quantize` writes them (lower bounds, then upper):
/// the merge (least lower and greatest upper bounds) and the overlap test (touching counts).
template <int Slabs>
void coarse_merge(std::int16_t into[2 * Slabs], const std::int16_t other[2 * Slabs]) {
  for (int s = 0; s < Slabs; ++s) {
    into[s] = std::min(into[s], other[s]);
    into[Slabs + s] = std::max(into[Slabs + s], other[Slabs + s]);
  }
}
template <int Slabs>
bool coarse_overlap(const std::int16_t a[2 * Slabs], const std::int16_t b[2 * Slabs]) {
  bool apart = false;
  for (int s = 0; s < Slabs; ++s) apart |= (a[s] > b[Slabs + s]) | (b[s] > a[Slabs + s]);
  return !apart;
}

std::int16_t random_bound(std::mt19937_64& rng) {
  // mostly a narrow range (so that volumes often overlap), sometimes the extremes
  switch (rng() % 8) {
    case 0: return std::numeric_limits<std::int16_t>::min();
    case 1: return std::numeric_limits<std::int16_t>::max();
    default: return static_cast<std::int16_t>(static_cast<int>(rng() % 200) - 100);
  }
}

CoarseDop random_dop(std::mt19937_64& rng, unsigned slabs) {
  CoarseDop d{};
  for (unsigned s = 0; s < slabs; ++s) {
    std::int16_t a = random_bound(rng), b = random_bound(rng);
    if (rng() % 16 != 0 && a > b) std::swap(a, b);  // a few empty ones too
    d.lo[s] = a;
    d.hi[s] = b;
  }
  return d;
}

}  // namespace

TEST(LaneMasks, EveryLevelMatchesThePlainTest) {
  const auto levels = test::available_levels();
  ASSERT_GE(levels.size(), 1u);
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 3000; ++trial) {
    const unsigned slabs = trial % 2 ? 9 : 3;
    const unsigned stride = 8u << (trial % 4);
    const unsigned n = static_cast<unsigned>(rng() % (stride + 1));
    // a block of n lanes, every other value garbage (never part of a result), and the slack
    std::vector<std::int16_t> rows(2 * slabs * stride + kLaneSlack);
    for (auto& v : rows) v = random_bound(rng);
    std::vector<CoarseDop> lanes(n);
    for (unsigned j = 0; j < n; ++j) {
      lanes[j] = random_dop(rng, slabs);
      for (unsigned s = 0; s < slabs; ++s) {
        rows[s * stride + j] = lanes[j].lo[s];
        rows[(slabs + s) * stride + j] = lanes[j].hi[s];
      }
    }
    const unsigned count = 1 + static_cast<unsigned>(rng() % 5);
    std::vector<CoarseDop> others(count);
    for (auto& o : others) o = random_dop(rng, slabs);
    std::vector<std::uint64_t> want(count, 0);
    for (unsigned i = 0; i < count; ++i)
      for (unsigned j = 0; j < n; ++j) {
        bool apart = false;
        for (unsigned s = 0; s < slabs; ++s)
          apart = apart || lanes[j].lo[s] > others[i].hi[s] || others[i].lo[s] > lanes[j].hi[s];
        want[i] |= std::uint64_t(!apart) << j;
      }
    for (const LaneKernels* k : levels) {
      std::vector<std::uint64_t> got(count, ~std::uint64_t(0));
      k->dops(rows.data(), stride, n, slabs, others.data(), count, got.data());
      ASSERT_EQ(got, want) << to_string(k->level) << " slabs " << slabs << " stride " << stride << " n " << n;
    }
  }
}

TEST(LaneMasks, LevelsAreNamedAndSelectable) {
  for (SimdLevel l : {SimdLevel::Scalar, SimdLevel::Sse2, SimdLevel::Avx2, SimdLevel::Avx512})
    EXPECT_EQ(parse_simd_level(to_string(l)), l);
  EXPECT_FALSE(parse_simd_level("avx1024"));
  const SimdLevel best = best_simd_level();
  ASSERT_NE(lane_kernels_for(best), nullptr);
  EXPECT_NE(lane_kernels_for(SimdLevel::Scalar), nullptr);
  const SimdLevel before = lane_kernels().level;
  select_simd_level(SimdLevel::Scalar);
  EXPECT_EQ(lane_kernels().level, SimdLevel::Scalar);
  select_simd_level(before);
  EXPECT_EQ(lane_kernels().level, before);
  if (best != SimdLevel::Avx512) {
    EXPECT_THROW(select_simd_level(SimdLevel::Avx512), Error);
  }
}

TEST(CoarseVolumes, NeverSeparateWhatFloatVolumesDoNot) {
  // Pairs of float 18-DOPs, on grids that hold them, that only partly hold them, and that are
  // far too coarse or fine; whenever the float volumes overlap, the coarse ones do.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> U(-1, 1);
  int overlapping = 0, separated = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const float scale = std::pow(10.0f, static_cast<float>(static_cast<int>(rng() % 9) - 4));
    Kdop18 box;
    for (int s = 0; s < 9; ++s) {
      box.lo[s] = -scale * (trial % 3 == 0 ? 0.1f : 1.0f);
      box.hi[s] = scale * (trial % 5 == 0 ? 1e-3f : 1.0f);
    }
    const CoarseGrid<9> grid = CoarseGrid<9>::over(box);
    Kdop18 a, b;
    // b against a along each slab: touching it exactly at either end or overlapping it (most
    // trials), on some slabs just apart or anywhere
    const int apart_slab = rng() % 3 == 0 ? static_cast<int>(rng() % 9) : -1;
    for (int s = 0; s < 9; ++s) {
      const float c = U(rng) * scale * 1.5f, w = std::abs(U(rng)) * scale * 0.05f;
      a.lo[s] = c - w, a.hi[s] = c + w;
      const float d = std::abs(U(rng)) * scale * 0.05f;
      const unsigned how = s == apart_slab ? 3 + rng() % 2 : rng() % 3;
      switch (how) {
        case 0: b.lo[s] = a.hi[s], b.hi[s] = a.hi[s] + d; break;
        case 1: b.lo[s] = a.lo[s] - d, b.hi[s] = a.lo[s]; break;
        case 2: b.lo[s] = c - d, b.hi[s] = c + d; break;
        case 3: b.lo[s] = std::nextafter(a.hi[s], 1e30f), b.hi[s] = b.lo[s] + d; break;
        default: b.lo[s] = U(rng) * scale, b.hi[s] = b.lo[s] + d; break;
      }
    }
    if (trial % 97 == 0) a.lo[trial % 9] = std::numeric_limits<float>::quiet_NaN();  // never separates
    if (trial % 89 == 0) b.hi[trial % 9] = std::numeric_limits<float>::infinity();
    std::int16_t ca[18], cb[18];
    grid.quantize(a, ca);
    grid.quantize(b, cb);
    const bool coarse = coarse_overlap<9>(ca, cb);
    if (a.overlaps(b)) {
      ++overlapping;
      ASSERT_TRUE(coarse) << "trial " << trial;
    } else {
      separated += !coarse;
    }
    // the scalar bounds are the vector ones
    for (int s = 0; s < 9; ++s) {
      ASSERT_EQ(ca[s], grid.lower(a.lo[s], s));
      ASSERT_EQ(ca[9 + s], grid.upper(a.hi[s], s));
    }
  }
  EXPECT_GT(overlapping, 1000);
  EXPECT_GT(separated, 1000);  // they do separate, where the float ones are apart by more than a cell
}

TEST(CoarseVolumes, MergeIsTheCoarseVolumeOfTheMerge) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<float> U(-2, 2);
  Kdop18 box;
  for (int s = 0; s < 9; ++s) box.lo[s] = -1, box.hi[s] = 1;
  const CoarseGrid<9> grid = CoarseGrid<9>::over(box);
  for (int trial = 0; trial < 5000; ++trial) {
    Kdop18 a, b;
    for (int s = 0; s < 9; ++s) {
      a.lo[s] = U(rng), a.hi[s] = a.lo[s] + std::abs(U(rng));
      b.lo[s] = U(rng), b.hi[s] = b.lo[s] + std::abs(U(rng));
    }
    std::int16_t ca[18], cb[18], cm[18];
    grid.quantize(a, ca);
    grid.quantize(b, cb);
    grid.quantize(Kdop18::merged(a, b), cm);
    coarse_merge<9>(ca, cb);
    ASSERT_TRUE(std::equal(ca, ca + 18, cm)) << trial;
  }
}

namespace {

/// The points' largest coordinate in [2^-60, 2^60]: what the kernel decides itself.
bool in_range(const CcdPoints& p) {
  double mx = 0;
  for (const auto* side : {&p.start, &p.end})
    for (const Vec3& v : *side) mx = std::max(mx, v.cwiseAbs().maxCoeff());
  return mx >= 0x1p-60 && mx <= 0x1p60;
}

/// What the kernels must return for a query: the filter's own result, or kUndecided.
std::uint8_t expected_quarters(CcdKind kind, const CcdPoints& p, unsigned within) {
  return in_range(p) ? static_cast<std::uint8_t>(coplanar_quarters(kind, p, 0.0, within)) : kUndecided;
}

/// expected_quarters of each query q (its four vertices ids[q] at the interleaved positions
/// x0 and x1, the quarters within[q]).
std::vector<std::uint8_t> expected_of(CcdKind kind, const std::vector<double>& x0, const std::vector<double>& x1,
                                      const std::vector<std::array<std::uint32_t, 4>>& ids,
                                      const std::vector<std::uint8_t>& within) {
  std::vector<std::uint8_t> expected(ids.size());
  for (std::size_t q = 0; q < ids.size(); ++q) {
    CcdPoints p;
    for (int k = 0; k < 4; ++k) {
      p.start[k] = Vec3(x0[3 * ids[q][k]], x0[3 * ids[q][k] + 1], x0[3 * ids[q][k] + 2]);
      p.end[k] = Vec3(x1[3 * ids[q][k]], x1[3 * ids[q][k] + 1], x1[3 * ids[q][k] + 2]);
    }
    expected[q] = expected_quarters(kind, p, within[q]);
  }
  return expected;
}

/// Every SIMD level's coplanar_quarters on the same queries gives `expected`.
void expect_every_level(CcdKind kind, const std::vector<double>& x0, const std::vector<double>& x1,
                        const std::vector<std::array<std::uint32_t, 4>>& ids, const std::vector<std::uint8_t>& within,
                        const std::vector<std::uint8_t>& expected) {
  const std::size_t n = ids.size();
  const std::unique_ptr<std::uint32_t[][4]> raw(new std::uint32_t[n][4]);
  for (std::size_t q = 0; q < n; ++q) std::copy(ids[q].begin(), ids[q].end(), raw[q]);
  for (const LaneKernels* k : test::available_levels()) {
    std::vector<std::uint8_t> got(n, 0x77);
    k->coplanar_quarters(kind == CcdKind::VertexFace, x0.data(), x1.data(), raw.get(), within.data(), n, got.data());
    ASSERT_EQ(got, expected) << to_string(k->level);
  }
}

}  // namespace

TEST(LaneMasks, CoplanarQuartersAreTheFiltersOwn) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> U(-1, 1);
  for (CcdKind kind : {CcdKind::VertexFace, CcdKind::EdgeEdge}) {
    // queries as position arrays indexed by vertex id: four fresh vertices each
    const std::size_t n = 3000;
    std::vector<double> x0(3 * 4 * n), x1(3 * 4 * n);
    std::vector<std::array<std::uint32_t, 4>> ids(n);
    std::vector<std::uint8_t> within(n);
    for (std::size_t q = 0; q < n; ++q) {
      within[q] = static_cast<std::uint8_t>(q % 5 == 0 ? 0xF : 1 + rng() % 15);
      const double scale = std::pow(2.0, static_cast<int>(rng() % 160) - 80);  // some beyond 2^+-60
      const double motion = (q % 3 == 0) ? 0.0 : std::pow(10.0, -static_cast<int>(rng() % 6));
      for (int k = 0; k < 4; ++k) {
        ids[q][k] = static_cast<std::uint32_t>(4 * q + static_cast<std::size_t>(3 - k));  // any order
        for (int c = 0; c < 3; ++c) {
          const double v = U(rng);
          const std::size_t i = 3 * ids[q][k] + c;
          x0[i] = scale * v;
          x1[i] = scale * (v + motion * U(rng));
          if (q % 7 == 0 && c == 2) x0[i] = x1[i] = 0.0;  // all in one plane: never removed
        }
      }
    }
    const std::vector<std::uint8_t> expected = expected_of(kind, x0, x1, ids, within);
    std::size_t removed = 0, kept = 0;
    for (std::uint8_t e : expected) {
      removed += e == 0;
      kept += e != 0 && e != kUndecided;
    }
    EXPECT_GT(removed, n / 4);
    EXPECT_GT(kept, n / 20);
    expect_every_level(kind, x0, x1, ids, within, expected);
  }
}

// Runs of queries whose cubic is of one sign over the whole step, as in a sub-step, fill whole
// registers (the kernels then skip the halves and quarters); every other run has one query in
// a plane (kept in every quarter asked for) at a different place in the run.
TEST(LaneMasks, CoplanarQuartersOfRunsOfOneSign) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(-1, 1);
  for (CcdKind kind : {CcdKind::VertexFace, CcdKind::EdgeEdge}) {
    const std::size_t run = 32, n = 40 * run;
    std::vector<double> x0(3 * 4 * n), x1(3 * 4 * n);
    std::vector<std::array<std::uint32_t, 4>> ids(n);
    std::vector<std::uint8_t> within(n);
    for (std::size_t q = 0; q < n; ++q) {
      const std::size_t r = q / run;
      const bool planar = r % 2 == 1 && q % run == r % run;
      within[q] = static_cast<std::uint8_t>(q % 3 == 0 ? 0xF : 1 + rng() % 15);
      for (int k = 0; k < 4; ++k) {
        ids[q][k] = static_cast<std::uint32_t>(4 * q + static_cast<std::size_t>(k));
        for (int c = 0; c < 3; ++c) {
          // a tetrahedron far from flat, moving by a thousandth of its size
          const double v = (c == k - 1 ? 1.0 : 0.0) + 0.1 * U(rng);
          const std::size_t i = 3 * ids[q][k] + c;
          x0[i] = v;
          x1[i] = v + 1e-3 * U(rng);
          if (planar && c == 2) x0[i] = x1[i] = 0.5;
        }
      }
    }
    const std::vector<std::uint8_t> expected = expected_of(kind, x0, x1, ids, within);
    std::size_t removed = 0, planar_kept = 0;
    for (std::size_t q = 0; q < n; ++q) {
      removed += expected[q] == 0;
      planar_kept += expected[q] == within[q] && (q / run) % 2 == 1 && q % run == (q / run) % run;
    }
    EXPECT_EQ(removed, n - n / run / 2) << "every query removed but the planar ones";
    EXPECT_EQ(planar_kept, n / run / 2) << "every planar query kept in the quarters asked for";
    expect_every_level(kind, x0, x1, ids, within, expected);
  }
}

TEST(LaneMasks, CoplanarQuartersMatchTheFilterAtItsErrorBounds) {
  // Queries flattened towards a plane until the filter's result changes: the cubic's
  // coefficients (or its halves' or quarters') then lie at their error bounds, and the kernels
  // must change between the same two neighbouring inputs (a bound any smaller or larger
  // changes elsewhere).
  const auto levels = test::available_levels();
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> U(-1, 1);
  int flips = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const CcdKind kind = trial % 2 ? CcdKind::EdgeEdge : CcdKind::VertexFace;
    const std::uint8_t within = static_cast<std::uint8_t>(trial % 3 == 0 ? 0xF : 1 + rng() % 15);
    double base0[12], base1[12];
    for (int i = 0; i < 12; ++i) base0[i] = U(rng), base1[i] = base0[i] + 0.3 * U(rng);
    auto points = [&](double lambda, double* x0, double* x1) {
      for (int i = 0; i < 12; ++i) {
        x0[i] = i % 3 == 2 ? base0[i] * lambda : base0[i];
        x1[i] = i % 3 == 2 ? base1[i] * lambda : base1[i];
      }
    };
    auto scalar = [&](double lambda) {
      double x0[12], x1[12];
      points(lambda, x0, x1);
      CcdPoints p;
      for (int k = 0; k < 4; ++k) {
        p.start[k] = Vec3(x0[3 * k], x0[3 * k + 1], x0[3 * k + 2]);
        p.end[k] = Vec3(x1[3 * k], x1[3 * k + 1], x1[3 * k + 2]);
      }
      return expected_quarters(kind, p, within);
    };
    const std::uint8_t at_one = scalar(1.0), at_zero = scalar(0x1p-200);
    if (at_one == at_zero) continue;
    double lo = 0x1p-200, hi = 1.0;  // scalar(lo) == at_zero, scalar(hi) != at_zero
    for (int it = 0; it < 200 && std::nextafter(lo, hi) != hi; ++it) {
      const double mid = std::sqrt(lo) * std::sqrt(hi);
      const double m = (mid > lo && mid < hi) ? mid : std::nextafter(lo, hi);
      (scalar(m) == at_zero ? lo : hi) = m;
    }
    ++flips;
    for (double lambda : {lo, hi}) {
      double x0[12], x1[12];
      points(lambda, x0, x1);
      const std::uint32_t ids[1][4] = {{0, 1, 2, 3}};
      for (const LaneKernels* k : levels) {
        std::uint8_t got = 0x77;
        k->coplanar_quarters(kind == CcdKind::VertexFace, x0, x1, ids, &within, 1, &got);
        ASSERT_EQ(got, scalar(lambda)) << to_string(k->level) << " trial " << trial << " lambda " << lambda;
      }
    }
  }
  EXPECT_GT(flips, 100);
}

TEST(CoarseVolumes, GridKeeperHoldsThePositionsAndKeepsItsGrid) {
  GridKeeper<9> keeper;
  const double lo[3] = {-1, -2, 0}, hi[3] = {1, 2, 0};  // a flat scene
  const CoarseGrid<9> first = keeper.fit(lo, hi);
  // the box's corners are inside the grid (not clamped to its ends), the flat axis too
  Kdop18 corner;
  for (int s = 0; s < 9; ++s) corner.lo[s] = corner.hi[s] = 0;
  corner.add_point(Vec3(-1, -2, 0));
  corner.add_point(Vec3(1, 2, 0));
  std::int16_t q[18];
  first.quantize(corner, q);
  for (int s = 0; s < 9; ++s) {
    EXPECT_GT(q[s], -32768) << s;
    EXPECT_LT(q[9 + s], 32767) << s;
  }
  // a small motion keeps the grid; leaving it or shrinking to a tenth makes a new one
  const double lo2[3] = {-1.1, -2, 0}, hi2[3] = {1, 2.1, 0.002};
  EXPECT_EQ(std::memcmp(&keeper.fit(lo2, hi2), &first, sizeof first), 0);
  const double lo3[3] = {-5, -2, 0}, hi3[3] = {1, 2, 0};
  EXPECT_NE(std::memcmp(&keeper.fit(lo3, hi3), &first, sizeof first), 0);
  const double lo4[3] = {-0.1, -0.2, 0}, hi4[3] = {0.1, 0.2, 0};
  const CoarseGrid<9> before = keeper.fit(lo3, hi3);
  EXPECT_NE(std::memcmp(&keeper.fit(lo4, hi4), &before, sizeof before), 0);
}

TEST(LaneMasks, MergesOfLanesMatchThePlainMerge) {
  const auto levels = test::available_levels();
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 2000; ++trial) {
    const unsigned slabs = trial % 2 ? 9 : 3;
    const unsigned stride = 8u << (trial % 4), out_stride = 8u << (rng() % 4);
    const unsigned lanes = 1 + static_cast<unsigned>(rng() % stride), n = static_cast<unsigned>(rng() % (out_stride + 1));
    const unsigned k = 2 + static_cast<unsigned>(rng() % 2);
    std::vector<std::int16_t> rows(2 * slabs * stride + kLaneSlack);
    for (auto& v : rows) v = random_bound(rng);
    std::uint8_t sources[3][kMaxLanes] = {};
    for (unsigned s = 0; s < k; ++s)
      for (unsigned j = 0; j < n; ++j) sources[s][j] = static_cast<std::uint8_t>(rng() % lanes);
    std::vector<std::int16_t> want(2 * slabs * out_stride, 7);
    for (unsigned r = 0; r < 2 * slabs; ++r)
      for (unsigned j = 0; j < n; ++j) {
        std::int16_t v = rows[r * stride + sources[0][j]];
        for (unsigned s = 1; s < k; ++s) {
          const std::int16_t w = rows[r * stride + sources[s][j]];
          v = r < slabs ? std::min(v, w) : std::max(v, w);
        }
        want[r * out_stride + j] = v;
      }
    for (const LaneKernels* kern : levels) {
      std::vector<std::int16_t> got(2 * slabs * out_stride, 7);  // lanes past n left as they are
      kern->merge_lanes(rows.data(), stride, slabs, sources, k, n, got.data(), out_stride);
      ASSERT_EQ(got, want) << to_string(kern->level) << " trial " << trial;
    }
  }
}

namespace {

/// A lane block of random coarse volumes for the pair and self kernels: n lanes of a
/// random stride that holds them, garbage in the other lanes and in the slack.
struct RandomBlock {
  std::vector<CoarseDop> lanes;
  std::vector<std::int16_t> rows;
  unsigned stride = 8;

  RandomBlock(std::mt19937_64& rng, unsigned slabs, unsigned n) : lanes(n) {
    while (stride < n || (stride < 64 && rng() % 4 == 0)) stride *= 2;
    rows.resize(2 * slabs * stride + kLaneSlack);
    for (auto& v : rows) v = random_bound(rng);
    for (unsigned j = 0; j < n; ++j) {
      lanes[j] = random_dop(rng, slabs);
      for (unsigned s = 0; s < slabs; ++s) {
        rows[s * stride + j] = lanes[j].lo[s];
        rows[(slabs + s) * stride + j] = lanes[j].hi[s];
      }
    }
  }
  unsigned n() const { return static_cast<unsigned>(lanes.size()); }
};

bool dops_meet(const CoarseDop& a, const CoarseDop& b, unsigned slabs) {
  for (unsigned s = 0; s < slabs; ++s)
    if (a.lo[s] > b.hi[s] || b.lo[s] > a.hi[s]) return false;
  return true;
}

/// Bit j set when lane j of `block` meets `d`.
std::uint64_t meeting(const RandomBlock& block, const CoarseDop& d, unsigned slabs) {
  std::uint64_t m = 0;
  for (unsigned j = 0; j < block.n(); ++j) m |= std::uint64_t(dops_meet(block.lanes[j], d, slabs)) << j;
  return m;
}

/// A leaf's three blocks (vertex, edge and face lanes of random sizes up to the kernels' limits)
/// and its own coarse volume.
struct RandomLeaf {
  RandomBlock vertices, edges, faces;
  CoarseDop leaf;
  RandomLeaf(std::mt19937_64& rng, unsigned slabs)
      : vertices(rng, slabs, static_cast<unsigned>(rng() % 33)),
        edges(rng, slabs, static_cast<unsigned>(rng() % 65)),
        faces(rng, slabs, static_cast<unsigned>(rng() % 33)),
        leaf(random_dop(rng, slabs)) {}
  LeafBlocks blocks() const {
    return {vertices.rows.data(), vertices.stride, vertices.n(), edges.rows.data(), edges.stride, edges.n(),
            faces.rows.data(),    faces.stride,    faces.n(),    &leaf};
  }
};

}  // namespace

// Every level's coarse tests of two leaves and of one leaf against the plain test of each pair
// of lanes: blocks of one register's lanes and of more (up to 64 edges), strides to 64, and
// garbage in the lanes past each block's end.
TEST(LaneMasks, PairAndSelfMasksMatchThePlainTestAtEveryLevel) {
  const auto levels = test::available_levels();
  std::mt19937_64 rng(23);
  for (int trial = 0; trial < 1500; ++trial) {
    const unsigned slabs = trial % 2 ? 9 : 3;
    const RandomLeaf a(rng, slabs), b(rng, slabs);
    const std::uint64_t va = meeting(a.vertices, b.leaf, slabs), vb = meeting(b.vertices, a.leaf, slabs);
    const std::uint64_t ea = meeting(a.edges, b.leaf, slabs), eb = meeting(b.edges, a.leaf, slabs);
    std::uint64_t chosen = 0;
    for (unsigned i = 0; i < a.edges.n(); ++i) chosen |= std::uint64_t(rng() % 2) << i;
    for (const LaneKernels* k : levels) {
      const std::string where = std::string(to_string(k->level)) + " trial " + std::to_string(trial);
      PairMasks m;
      k->pair_masks(slabs, a.blocks(), b.blocks(), m);
      ASSERT_EQ(m.alive_va, va) << where;
      ASSERT_EQ(m.alive_vb, vb) << where;
      ASSERT_EQ(m.alive_ea, ea) << where;
      for (std::uint64_t left = va; left; left &= left - 1) {
        const unsigned j = static_cast<unsigned>(std::countr_zero(left));
        ASSERT_EQ(m.vertex_faces_ab[j], meeting(b.faces, a.vertices.lanes[j], slabs)) << where << " vertex " << j;
      }
      for (std::uint64_t left = vb; left; left &= left - 1) {
        const unsigned j = static_cast<unsigned>(std::countr_zero(left));
        ASSERT_EQ(m.vertex_faces_ba[j], meeting(a.faces, b.vertices.lanes[j], slabs)) << where << " vertex " << j;
      }
      if (ea && eb) {  // the edges' pairs only where both sides have edges alive
        ASSERT_EQ(m.alive_eb, eb) << where;
        for (std::uint64_t left = ea; left; left &= left - 1) {
          const unsigned i = static_cast<unsigned>(std::countr_zero(left));
          ASSERT_EQ(m.edges[i], meeting(b.edges, a.edges.lanes[i], slabs) & eb) << where << " edge " << i;
        }
      }
      SelfMasks s;
      k->self_masks(slabs, a.blocks(), chosen, s);
      for (unsigned j = 0; j < a.vertices.n(); ++j)
        ASSERT_EQ(s.vertex_faces[j], meeting(a.faces, a.vertices.lanes[j], slabs)) << where << " vertex " << j;
      for (std::uint64_t left = chosen; left; left &= left - 1) {
        const unsigned i = static_cast<unsigned>(std::countr_zero(left));
        ASSERT_EQ(s.edges[i], meeting(a.edges, a.edges.lanes[i], slabs)) << where << " edge " << i;
      }
    }
  }
}
