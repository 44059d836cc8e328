// The BVH build through the engine's executor: a range large enough that its split's bounds
// and bins are found in chunks in parallel gives the same tree as the serial build, in arenas
// of 1, 2 and 3 threads, and its root splits where a plain one-pass binned SAH over all the
// triangles says it should.
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <limits>
#include <random>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/parallel/tbb_executor.h>

using namespace mccd;

namespace {

/// Small triangles' boxes in three clusters of different sizes and densities, stored one
/// cluster after the other as a scene's meshes are: 60% of n, 30%, then a far one of 10% at
/// the end (the last chunks of a split's range are all of it).
std::vector<TriangleBounds> clustered(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  const std::array<Vec3, 3> centre = {Vec3(0, 0, 0), Vec3(5, 1, 0.5), Vec3(30, 6, -3)};
  const std::array<double, 3> radius = {1.0, 0.4, 2.5};
  std::vector<TriangleBounds> t(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t c = i < n * 6 / 10 ? 0 : (i < n * 9 / 10 ? 1 : 2);
    const Vec3 p = centre[c] + radius[c] * Vec3(U(rng), U(rng), U(rng));
    const Vec3 size = 0.01 * Vec3(U(rng), U(rng), U(rng));
    t[i] = {p, p + size, p + 0.5 * size};
  }
  return t;
}

/// n small triangles' boxes spread evenly through the unit cube, then `slab` more in the slab
/// 0.70 <= x < 0.75, stored last, the very last one moved out to (1.7, 1.7, 1.7): the split
/// of the whole moves with how many of the last ones it counts and with the bounds it finds.
std::vector<TriangleBounds> cube_and_slab(std::size_t n, std::size_t slab, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<TriangleBounds> t(n + slab);
  for (std::size_t i = 0; i < n + slab; ++i) {
    const Vec3 p(i < n ? U(rng) : 0.70 + 0.05 * U(rng), U(rng), U(rng));
    const Vec3 size = 0.001 * Vec3(U(rng), U(rng), U(rng));
    t[i] = {p, p + size, p + 0.5 * size};
  }
  t.back() = {Vec3(1.7, 1.7, 1.7), Vec3(1.701, 1.701, 1.701), Vec3(1.7005, 1.7005, 1.7005)};
  return t;
}

bool same_tree(const BvhTopology& a, const BvhTopology& b) {
  if (a.size() != b.size() || a.depth() != b.depth() || a.triangle_order() != b.triangle_order()) return false;
  for (std::uint32_t i = 0; i < a.size(); ++i)
    if (a.nodes()[i].end != b.nodes()[i].end || a.nodes()[i].right_or_leaf != b.nodes()[i].right_or_leaf)
      return false;
  return true;
}

/// The triangles the root's left child should hold: the binned SAH of the build (32 bins of
/// the centroids' bounds per axis, a side's cost its box's half area times the leaves its
/// triangles make at least), found in one plain pass over every triangle.
std::vector<std::uint32_t> reference_left(const std::vector<TriangleBounds>& t, unsigned max_leaf) {
  constexpr int kBins = 32;
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3 mn = Vec3::Constant(inf), mx = -mn;
  for (const TriangleBounds& x : t) mn = mn.cwiseMin(x.centroid), mx = mx.cwiseMax(x.centroid);
  auto bin_of = [&](const TriangleBounds& x, int a) {
    return std::min(kBins - 1, static_cast<int>((x.centroid[a] - mn[a]) * (kBins / (mx[a] - mn[a]))));
  };
  auto half_area = [](const Vec3& lo, const Vec3& hi) {
    const Vec3 d = hi - lo;
    return d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
  };
  auto leaves = [&](std::size_t n) { return double((n + max_leaf - 1) / max_leaf); };
  double best = inf;
  int best_axis = -1, best_bin = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b + 1 < kBins; ++b) {
      Vec3 llo = Vec3::Constant(inf), lhi = -llo, rlo = llo, rhi = lhi;
      std::size_t nl = 0, nr = 0;
      for (const TriangleBounds& x : t) {
        if (bin_of(x, a) <= b)
          llo = llo.cwiseMin(x.lo), lhi = lhi.cwiseMax(x.hi), ++nl;
        else
          rlo = rlo.cwiseMin(x.lo), rhi = rhi.cwiseMax(x.hi), ++nr;
      }
      if (nl == 0 || nr == 0) continue;
      const double cost = half_area(llo, lhi) * leaves(nl) + half_area(rlo, rhi) * leaves(nr);
      if (cost < best) best = cost, best_axis = a, best_bin = b;
    }
  std::vector<std::uint32_t> left;
  for (std::uint32_t i = 0; i < t.size(); ++i)
    if (bin_of(t[i], best_axis) <= best_bin) left.push_back(i);
  return left;
}

/// Where the triangles of node n's subtree start in triangle_order() (its leftmost leaf's).
std::uint32_t first_triangle(const BvhTopology& b, std::uint32_t n) {
  while (!b.leaf(n)) n = b.left(n);
  return b.leaf_first(n);
}

}  // namespace

TEST(BvhBuild, LargeRangeSplitInChunksIsTheSerialTreeInEveryArena) {
  const std::vector<TriangleBounds> t = clustered(70000, 3);  // over twice the parallel split's size
  const BvhTopology serial(t, BvhBuild::Sah, 8);
  for (int threads : {1, 2, 3}) {
    tbb::task_arena arena(threads);
    BvhTopology parallel;
    arena.execute([&] { parallel = BvhTopology(t, BvhBuild::Sah, 8, {}, nullptr, detail::tbb_executor()); });
    EXPECT_TRUE(same_tree(parallel, serial)) << threads << " threads";
  }
}

TEST(BvhBuild, LargeRangeRootSplitsWhereOnePassBinnedSahSays) {
  const std::vector<std::vector<TriangleBounds>> scenes = {clustered(50000, 3), clustered(50000, 8),
                                                           cube_and_slab(40000, 5000, 5),
                                                           cube_and_slab(60000, 3000, 6)};
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    const std::vector<TriangleBounds>& t = scenes[k];
    BvhTopology b;
    tbb::task_arena arena(2);
    arena.execute([&] { b = BvhTopology(t, BvhBuild::Sah, 8, {}, nullptr, detail::tbb_executor()); });
    ASSERT_FALSE(b.leaf(0));
    std::vector<std::uint32_t> got(b.triangle_order().begin() + first_triangle(b, b.left(0)),
                                   b.triangle_order().begin() + first_triangle(b, b.right(0)));
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, reference_left(t, 8)) << "scene " << k;
  }
}
