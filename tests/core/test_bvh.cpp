#include <mccd/core/bvh.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
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
    for (unsigned leaf_size : {1u, 2u, 3u, 4u, 5u, 8u, 13u, 16u, 17u, 21u}) {
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

TEST(Bvh, ClosedComponentsGetTheirOwnSubtrees) {
  // Twelve small closed spheres packed closer than their size, threaded on a strip of open
  // triangles, all in one mesh, then a second mesh: with the faces, each sphere's triangles
  // are exactly those under one node, whatever SAH would have cut; the strip stays together
  // with the rest of its mesh; without them the tree is the plain SAH one.
  std::vector<Triangle> faces;
  std::vector<TriangleBounds> bounds;
  std::vector<std::vector<std::uint32_t>> spheres;
  std::uint32_t next = 0;
  auto add = [&](const std::array<Vec3, 3>& p, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    faces.push_back({a, b, c});
    bounds.push_back({p[0].cwiseMin(p[1]).cwiseMin(p[2]), p[0].cwiseMax(p[1]).cwiseMax(p[2]), (p[0] + p[1] + p[2]) / 3});
  };
  for (int k = 0; k < 12; ++k) {  // octahedra: 6 vertices, 8 triangles, closed
    const Vec3 c(0.3 * k, 0.1 * (k % 3), 0);
    const Vec3 v[6] = {c + Vec3(0.25, 0, 0), c - Vec3(0.25, 0, 0), c + Vec3(0, 0.25, 0),
                       c - Vec3(0, 0.25, 0), c + Vec3(0, 0, 0.25), c - Vec3(0, 0, 0.25)};
    const int tri[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    spheres.emplace_back();
    for (const auto& t : tri) {
      spheres.back().push_back(static_cast<std::uint32_t>(faces.size()));
      add({v[t[0]], v[t[1]], v[t[2]]}, next + t[0], next + t[1], next + t[2]);
    }
    next += 6;
  }
  for (int k = 0; k < 40; ++k) {  // an open strip through them
    const Vec3 a(0.1 * k, 0, 0), b(0.1 * k + 0.1, 0, 0), c(0.1 * k, 0.05, 0.01);
    add({a, b, c}, next, next + 1, next + 2);
    next += 3;
  }
  const std::size_t first_mesh = faces.size();
  for (int k = 0; k < 5; ++k) {  // a second mesh of loose triangles
    const Vec3 a(0.5 * k, 1, 0), b(0.5 * k + 0.1, 1, 0), c(0.5 * k, 1.1, 0);
    add({a, b, c}, next, next + 1, next + 2);
    next += 3;
  }
  const std::vector<std::size_t> offsets{0, first_mesh, faces.size()};
  BvhTopology b(bounds, BvhBuild::Sah, 4, offsets, &faces);
  std::vector<int> seen(faces.size(), 0);
  for (std::uint32_t i = 0; i < b.size(); ++i)
    if (b.leaf(i))
      for (std::uint32_t k = 0; k < b.leaf_count(i); ++k) ++seen[b.leaf_triangles(i)[k]];
  for (int s : seen) EXPECT_EQ(s, 1);
  auto below = [&](std::uint32_t n) {
    std::vector<std::uint32_t> t;
    for (std::uint32_t i = n; i < n + b.subtree_size(n); ++i)
      if (b.leaf(i)) t.insert(t.end(), b.leaf_triangles(i), b.leaf_triangles(i) + b.leaf_count(i));
    std::sort(t.begin(), t.end());
    return t;
  };
  for (const auto& sphere : spheres) {
    bool found = false;
    for (std::uint32_t i = 0; i < b.size() && !found; ++i) found = below(i) == sphere;
    EXPECT_TRUE(found);
  }
  // every node knows its mesh; the root spans both
  EXPECT_EQ(b.mesh_of_node(0), BvhTopology::kMixed);
  for (std::uint32_t i = 0; i < b.size(); ++i)
    if (b.leaf(i)) {
      EXPECT_EQ(b.mesh_of_node(i), b.leaf_triangles(i)[0] < first_mesh ? 0u : 1u);
    }
  // the median build (the paper's) ignores the faces
  BvhTopology m(bounds, BvhBuild::Median, 1, offsets, &faces);
  BvhTopology m0(bounds, BvhBuild::Median, 1, offsets);
  EXPECT_EQ(m.triangle_order(), m0.triangle_order());
}
