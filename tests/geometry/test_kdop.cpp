#include <mccd/geometry/kdop.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

using namespace mccd;

TEST(Kdop, ContainsItsPointsAfterFloatRounding) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int i = 0; i < 2000; ++i) {
    const double scale = std::pow(10.0, int(rng() % 12) - 6);
    Kdop18 d = Kdop18::empty();
    Aabb b = Aabb::empty();
    std::vector<Vec3> pts;
    for (int k = 0; k < 6; ++k) {
      pts.emplace_back(Vec3(U(rng), U(rng), U(rng)) * scale + Vec3::Constant(1000 * U(rng)));
      d.add_point(pts.back());
      b.add_point(pts.back());
    }
    for (auto& p : pts) {
      EXPECT_TRUE(d.contains(p));
      EXPECT_TRUE(b.contains(p));
      // every point on a segment between two of them is inside too (convexity)
      EXPECT_TRUE(d.contains(0.5 * (pts[0] + pts[3])));
    }
  }
}

TEST(Kdop, OverlapIsSymmetricAndDiagonalSeparates) {
  // a: the triangle (0,0)-(1,0)-(0,1); b: a segment just beyond its hypotenuse
  const std::vector<Vec3> pa = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const std::vector<Vec3> pb = {Vec3(1, 1, 0), Vec3(0.9, 0.9, 0)};
  Kdop18 a = Kdop18::empty(), b = Kdop18::empty();
  Aabb aa = Aabb::empty(), bb = Aabb::empty();
  for (const Vec3& p : pa) a.add_point(p), aa.add_point(p);
  for (const Vec3& p : pb) b.add_point(p), bb.add_point(p);
  // AABBs overlap, but the x+y slab separates them
  EXPECT_TRUE(aa.overlaps(bb));
  EXPECT_FALSE(a.overlaps(b));
  EXPECT_FALSE(b.overlaps(a));
  b.add_point(Vec3(0.5, 0.5, 0));  // now touching the hypotenuse
  EXPECT_TRUE(a.overlaps(b));
  EXPECT_TRUE(b.overlaps(a));
  EXPECT_FALSE(Kdop18::empty().overlaps(a));
}

TEST(Kdop, InflateCoversDistance) {
  Kdop18 a = Kdop18::empty(), b = Kdop18::empty();
  a.add_point(Vec3(0, 0, 0));
  b.add_point(Vec3(0.3, 0.3, 0.3));  // distance 0.5196
  EXPECT_FALSE(a.overlaps(b));
  // both inflated by the distance: every slab gap (at most sqrt(2) * 0.5196) is covered
  Kdop18 a2 = a, b2 = b;
  a2.inflate(0.52);
  b2.inflate(0.52);
  EXPECT_TRUE(a2.overlaps(b2));
  // inflated by half the distance, the x+y slab (gap 0.6) still separates them
  Kdop18 a3 = a, b3 = b;
  a3.inflate(0.26);
  b3.inflate(0.26);
  EXPECT_FALSE(a3.overlaps(b3));
}

TEST(Kdop, FloatStepsMatchNextafter) {
  const float inf = std::numeric_limits<float>::infinity();
  std::mt19937 rng(11);
  std::vector<float> values = {0.0f, -0.0f, 1.0f, -1.0f, std::numeric_limits<float>::denorm_min(),
                               -std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::max(),
                               -std::numeric_limits<float>::max(), std::numeric_limits<float>::min(), inf, -inf};
  for (int i = 0; i < 10000; ++i) {
    std::uint32_t u = rng();
    float f;
    std::memcpy(&f, &u, 4);
    if (f == f) values.push_back(f);
  }
  for (float f : values) {
    EXPECT_EQ(float_down(f), std::nextafter(f, -inf)) << f;
    EXPECT_EQ(float_up(f), std::nextafter(f, inf)) << f;
  }
}

TEST(Kdop, OverlapAndMergeEqualTheSlabDefinitions) {
  // The vectorised test against the definition, slab by slab, on random volumes that often
  // touch exactly, with infinities and NaN bounds thrown in.
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick(0, 6);
  const float specials[] = {0.0f, 1.0f, -1.0f, std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(), 0.5f};
  auto random_dop = [&] {
    Kdop18 d;
    for (int i = 0; i < 9; ++i) {
      d.lo[i] = specials[pick(rng)];
      d.hi[i] = specials[pick(rng)];
    }
    return d;
  };
  int overlaps = 0;
  for (int n = 0; n < 200000; ++n) {
    const Kdop18 a = random_dop(), b = random_dop();
    bool sep = false;
    for (int i = 0; i < 9; ++i) sep = sep || a.lo[i] > b.hi[i] || b.lo[i] > a.hi[i];
    ASSERT_EQ(a.overlaps(b), !sep) << n;
    Kdop18 m = a;
    m.merge(b);
    for (int i = 0; i < 9; ++i) {
      const float lo = b.lo[i] < a.lo[i] ? b.lo[i] : a.lo[i], hi = b.hi[i] > a.hi[i] ? b.hi[i] : a.hi[i];
      ASSERT_TRUE(std::memcmp(&m.lo[i], &lo, 4) == 0 && std::memcmp(&m.hi[i], &hi, 4) == 0) << n << " slab " << i;
    }
    overlaps += !sep;
  }
  EXPECT_GT(overlaps, 0);
}
