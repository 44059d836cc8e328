#include <mccd/geometry/kdop.h>

#include <gtest/gtest.h>

#include <cmath>
#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

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

TEST(Kdop, FloatStepsOutsideARoundedDoubleHoldIt) {
  // float_step_down / float_step_up of x rounded to float (to nearest, with or without
  // flush-to-zero) lie at most / at least at x, and within two units in the last place (and the
  // smallest normal float) of the nearest floats outside x; the 4-lane versions equal the scalar ones bit for bit.
  const double inf = std::numeric_limits<double>::infinity();
  const float fmax = std::numeric_limits<float>::max();
  std::vector<double> values = {0.0, -0.0, 1.0, -1.0, 0.1, -0.1, 1e-45, -1e-45, 1e-50, -1e-50, 3.4028235e38,
                                -3.4028235e38, 1e39, -1e39, 1e300, -1e300, inf, -inf, 0x1p-126, -0x1p-126,
                                static_cast<double>(fmax), static_cast<double>(std::numeric_limits<float>::denorm_min())};
  std::mt19937_64 rng(5);
  for (int i = 0; i < 20000; ++i) {
    std::uint64_t u = rng();
    double x;
    std::memcpy(&x, &u, 8);
    if (x == x) values.push_back(x);
    values.push_back(std::ldexp(static_cast<double>(rng() % 2000001) - 1e6, static_cast<int>(rng() % 80) - 40));
  }
  // The nearest floats outside x (the reference of how far the steps may go).
  auto below = [](double x) {
    const float f = static_cast<float>(x);
    return static_cast<double>(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
  };
  auto above = [](double x) {
    const float f = static_cast<float>(x);
    return static_cast<double>(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
  };
  auto two_down = [](float f) { return float_down(float_down(f)); };
  auto two_up = [](float f) { return float_up(float_up(f)); };
  // The checks; `tight`: without flushing of subnormals, where the steps must also stay close.
  auto check = [&](bool tight) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double x = values[i];
      const float f = static_cast<float>(x);
      const float lo = float_step_down(f), hi = float_step_up(f);
      ASSERT_LE(static_cast<double>(lo), x) << x;
      ASSERT_GE(static_cast<double>(hi), x) << x;
      if (tight && std::abs(x) >= 0x1p-126 && std::abs(x) <= static_cast<double>(fmax)) {
        // (plus the absolute step of the smallest normal float)
        ASSERT_GE(static_cast<double>(lo), static_cast<double>(two_down(static_cast<float>(below(x)))) - 0x1p-126) << x;
        ASSERT_LE(static_cast<double>(hi), static_cast<double>(two_up(static_cast<float>(above(x)))) + 0x1p-126) << x;
      }
#if defined(__SSE2__)
      if (i + 4 > values.size()) continue;
      float four[4], lo4[4], hi4[4];
      for (int k = 0; k < 4; ++k) four[k] = static_cast<float>(values[i + k]);
      _mm_storeu_ps(lo4, floats_down(_mm_loadu_ps(four)));
      _mm_storeu_ps(hi4, floats_up(_mm_loadu_ps(four)));
      for (int k = 0; k < 4; ++k) {
        const float lo1 = float_step_down(four[k]), hi1 = float_step_up(four[k]);
        ASSERT_EQ(std::memcmp(&lo4[k], &lo1, 4), 0) << values[i + k];
        ASSERT_EQ(std::memcmp(&hi4[k], &hi1, 4), 0) << values[i + k];
      }
#endif
    }
  };
#if defined(__SSE2__)
  // With and without flushing, the control word restored however the checks end.
  struct Restore {
    unsigned csr = _mm_getcsr();
    ~Restore() { _mm_setcsr(csr); }
  } restore;
  constexpr unsigned kDaz = 0x0040u;  // denormals are zero
  for (bool flush : {false, true}) {
    _mm_setcsr((restore.csr & ~(_MM_ROUND_MASK | _MM_FLUSH_ZERO_MASK | kDaz)) | _MM_ROUND_NEAREST |
               (flush ? _MM_FLUSH_ZERO_ON | kDaz : 0u));
    SCOPED_TRACE(flush ? "flush-to-zero and denormals-are-zero" : "IEEE subnormals");
    check(!flush);
    if (HasFatalFailure()) return;
  }
#else
  check(true);
#endif
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
