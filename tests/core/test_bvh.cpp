#include <mccd/core/bvh.h>

#include <gtest/gtest.h>

#include <random>

#include <mccd/geometry/kdop.h>

using namespace mccd;

namespace {
/// Point-like triangles at the given centroids (box = the point).
std::vector<TriangleBounds> points(const std::vector<Vec3>& c) {
  std::vector<TriangleBounds> t;
  for (const Vec3& p : c) t.push_back({p, p + Vec3(0.01, 0.02, 0.0), p});
  return t;
}
}  // namespace

TEST(Bvh, DepthFirstLayoutInvariants) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> U(0, 1);
  for (int n : {1, 2, 3, 7, 100, 1000}) {
    std::vector<Vec3> c(n);
    for (auto& p : c) p = Vec3(U(rng), U(rng) * 3, U(rng) * 0.1);
    if (n == 100)
      for (auto& p : c) p = Vec3(1, 1, 1);  // all equal: count-median fallback
    for (BvhBuild kind : {BvhBuild::Median, BvhBuild::Sah})
    for (unsigned leaf_size : {1u, 2u, 3u, 4u, 5u, 8u, 13u, 16u}) {
    BvhTopology b(points(c), kind, leaf_size);
    if (leaf_size == 1) {
      ASSERT_EQ(b.size(), std::size_t(2 * n - 1));
    }
    std::vector<int> seen(n, 0);
    std::size_t leaves = 0;
    for (std::uint32_t i = 0; i < b.size(); ++i) {
      if (b.leaf(i)) {
        ++leaves;
        ASSERT_GE(b.leaf_count(i), 1u);
        ASSERT_LE(b.leaf_count(i), leaf_size);
        for (std::uint32_t k = 0; k < b.leaf_count(i); ++k) ++seen[b.leaf_triangles(i)[k]];
      } else {
        EXPECT_EQ(b.nodes()[b.left(i)].end, b.right(i));  // left subtree ends where right starts
        EXPECT_EQ(b.nodes()[b.right(i)].end, b.nodes()[i].end);
      }
    }
    for (int s : seen) EXPECT_EQ(s, 1);
    EXPECT_EQ(b.size(), 2 * leaves - 1);
    if (n == 1000) {
      EXPECT_LT(b.depth(), 40u);
    }
    }
  }
}

TEST(Bvh, RefitContainsChildren) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> U(-1, 1);
  std::vector<Vec3> c(257);
  for (auto& p : c) p = Vec3(U(rng), U(rng), U(rng));
  BvhTopology b(points(c), BvhBuild::Sah);
  std::vector<Kdop18> vol(b.size());
  refit_range(b, vol, 0, std::uint32_t(b.size()), [&](std::uint32_t node) {
    Kdop18 d = Kdop18::empty();
    for (std::uint32_t k = 0; k < b.leaf_count(node); ++k) {
      const std::uint32_t t = b.leaf_triangles(node)[k];
      d.add_point(c[t]);
      d.add_point(c[t] + Vec3(0.01, 0, 0));
    }
    return d;
  });
  for (std::uint32_t i = 0; i < b.size(); ++i)
    if (!b.leaf(i))
      for (std::uint32_t ch : {b.left(i), b.right(i)})
        for (int k = 0; k < 9; ++k) {
          EXPECT_LE(vol[i].lo[k], vol[ch].lo[k]);
          EXPECT_GE(vol[i].hi[k], vol[ch].hi[k]);
        }
  for (std::size_t t = 0; t < c.size(); ++t) EXPECT_TRUE(vol[0].contains(c[t]));
}
