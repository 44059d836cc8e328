// The coplanarity filter of the broad phase never clears the quarter of a true contact: its
// mask against the exact GMP reference on queries built to touch exactly (often at a quarter
// boundary), perturbed or not, and on random queries.
#include <mccd/geometry/ccd_filter.h>

#include <gtest/gtest.h>

#include <random>

#include "support/exact_ccd.h"

using namespace mccd;
using namespace mccd::detail;

namespace {

CcdPoints touching_query(std::mt19937_64& rng, bool vf) {
  auto grid = [&](int range) { return std::ldexp(double(std::uniform_int_distribution<int>(-range, range)(rng)), -8); };
  auto vec = [&] { return Vec3(grid(256), grid(256), grid(256)); };
  const double tc = std::ldexp(double(std::uniform_int_distribution<int>(0, 16)(rng)), -4);  // k/16
  std::array<Vec3, 4> at;  // positions at tc, touching
  if (vf) {
    at[1] = vec(), at[2] = vec(), at[3] = vec();
    const double u = std::ldexp(double(std::uniform_int_distribution<int>(0, 8)(rng)), -4);
    const double w = std::ldexp(double(std::uniform_int_distribution<int>(0, 8)(rng)), -4);
    at[0] = at[1] * u + at[2] * w + at[3] * (1 - u - w);
  } else {
    at[0] = vec(), at[1] = vec(), at[2] = vec();
    const double s = std::ldexp(double(std::uniform_int_distribution<int>(0, 16)(rng)), -4);
    const Vec3 x = at[0] * (1 - s) + at[1] * s;  // a point of edge a, which edge b passes through
    at[3] = x + (x - at[2]);
  }
  CcdPoints p;
  for (int i = 0; i < 4; ++i) {
    const Vec3 v = vec();  // velocity; positions at 0 and 1 from the touching ones
    p.start[i] = at[i] - v * tc;
    p.end[i] = at[i] + v * (1 - tc);
  }
  if (std::uniform_int_distribution<int>(0, 2)(rng) == 0) p.end[0].x() += std::ldexp(1.0, -40);
  return p;
}

void check(const CcdPoints& p, bool vf, int& hits) {
  const test::ExactResult ex = vf ? test::exact_vertex_face(p) : test::exact_edge_edge(p);
  const unsigned mask = coplanar_quarters(vf ? CcdKind::VertexFace : CcdKind::EdgeEdge, p, 0.0);
  if (!ex.hit) return;
  ++hits;
  int q = 0;  // the last quarter starting at or before the contact time
  for (int k = 1; k < 4; ++k)
    if (test::time_not_after(0.25 * k, ex.toi)) q = k;
  ASSERT_TRUE(mask & (1u << q)) << (vf ? "VF" : "EE") << " contact in quarter " << q << ", mask " << mask;
}

}  // namespace

TEST(CcdFilter, NeverClearsTheQuarterOfAContact) {
  std::mt19937_64 rng(2024);
  int hits = 0;
  for (int n = 0; n < 4000; ++n) {
    const bool vf = n % 2 == 0;
    check(touching_query(rng, vf), vf, hits);
  }
  EXPECT_GT(hits, 2000);
}

TEST(CcdFilter, ClearsPairsThatAreNeverCoplanar) {
  // A vertex moving parallel to a face, above it: never coplanar, no quarter.
  CcdPoints p;
  p.start = {Vec3(0.2, 0.2, 1), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  p.end = {Vec3(0.3, 0.3, 1), Vec3(0, 0, 0.1), Vec3(1, 0, 0.1), Vec3(0, 1, 0.1)};
  EXPECT_EQ(coplanar_quarters(CcdKind::VertexFace, p, 0.0), 0u);
  // dropping through at t = 0.6: only quarter 2 ([0.5, 0.75]) can hold it
  p.end[0] = Vec3(0.3, 0.3, -0.6);
  p.end[1].z() = p.end[2].z() = p.end[3].z() = 0;
  EXPECT_EQ(coplanar_quarters(CcdKind::VertexFace, p, 0.0), 4u);
  EXPECT_EQ(coplanar_quarters(CcdKind::VertexFace, p, 0.0, 0b1011u), 0u);  // quarter 2 not asked for
  EXPECT_EQ(coplanar_quarters(CcdKind::VertexFace, p, 0.0, 0b0110u), 4u);
  // within a distance larger than the motion: every quarter
  EXPECT_EQ(coplanar_quarters(CcdKind::VertexFace, p, 10.0), 15u);
}

TEST(CcdFilter, TestAfterTheFilterEqualsTheWholeTest) {
  // FilteredCcd::test continues the filter's setup: where the swept boxes meet, the same
  // answers, times of impact and counts as the elementary tests called from scratch, on
  // touching and random queries, with and without a minimum distance.
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> U(-1, 1);
  int compared = 0;
  for (int n = 0; n < 6000; ++n) {
    const bool vf = n % 2 == 0;
    CcdPoints p = n % 3 == 0 ? touching_query(rng, vf) : CcdPoints{};
    if (n % 3 != 0)
      for (int i = 0; i < 4; ++i) p.start[i] = Vec3(U(rng), U(rng), U(rng)), p.end[i] = Vec3(U(rng), U(rng), U(rng));
    const CcdOptions options{n % 5 == 0 ? 0.01 : 0.0};
    const CcdKind kind = vf ? CcdKind::VertexFace : CcdKind::EdgeEdge;
    CcdCounters whole, filtered;
    double toi_whole = -1, toi_filtered = -1;
    const bool hit_whole = vf ? vertex_face_ccd(p, toi_whole, options, &whole) : edge_edge_ccd(p, toi_whole, options, &whole);
    FilteredCcd f;
    if (!f.filter(kind, p, options.min_distance)) {
      ASSERT_FALSE(hit_whole) << n;  // the filter never clears a contact
      continue;
    }
    if (!ccd_box_overlap(kind, p, options.min_distance)) continue;  // the whole test stops at stage (a)
    ++compared;
    const bool hit_filtered = f.test(toi_filtered, &filtered);
    ASSERT_EQ(hit_filtered, hit_whole) << n;
    if (hit_whole) {
      ASSERT_EQ(toi_filtered, toi_whole) << n;
    }
    EXPECT_EQ(filtered.hits, whole.hits);
    EXPECT_EQ(filtered.root_tests, whole.root_tests);
    EXPECT_EQ(filtered.pieces, whole.pieces);
    EXPECT_EQ(filtered.fast_hits, whole.fast_hits);
  }
  EXPECT_GT(compared, 1500);
}
