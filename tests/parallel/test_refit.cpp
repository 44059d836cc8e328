// The refit (parallel/refit.h): RefitPlan::run, subtrees in parallel under a static partition
// and the nodes above them serially, gives bit for bit the node volumes of a plain recursive
// merge from the leaves; with a BVH of one subtree (refitted serially) and with one cut into
// many subtrees; with static subtrees refitted once by run_static() and never by run(); in
// the default arena and in arenas of 1 and 3 threads.
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <atomic>
#include <mutex>
#include <set>

#include <mccd/parallel/refit.h>

#include "fixtures/scenes.h"
#include "support/bvtt_fixture.h"

using namespace mccd;
using namespace mccd::detail;
using test::BvttScene;
using test::NodeVolume;

namespace {

/// Every node volume equal to the reference, bit for bit.
::testing::AssertionResult same_volumes(const LargeVector<NodeVolume>& got, const LargeVector<NodeVolume>& want) {
  if (got.size() != want.size()) return ::testing::AssertionFailure() << got.size() << " volumes, " << want.size();
  for (std::size_t i = 0; i < got.size(); ++i)
    if (!test::same_volume(got[i], want[i])) return ::testing::AssertionFailure() << "node " << i << " differs";
  return ::testing::AssertionSuccess();
}

/// A value no refit produces (each quarter a point far away): what a node not refitted keeps.
NodeVolume poison() {
  NodeVolume v = NodeVolume::empty();
  Kdop18 d = Kdop18::empty();
  d.add_point(Vec3(1e6, -1e6, 1e6));
  for (int q = 0; q < 4; ++q) v.set(q, d);
  return v;
}

/// run() at every step of `s` (volumes poisoned first) against the reference.
void expect_run_matches_reference(BvttScene& s, const RefitPlan& plan) {
  LargeVector<NodeVolume> want;
  for (std::size_t f = 0; f < s.steps(); ++f) {
    s.reference_volumes(f, want);
    LargeVector<NodeVolume> got(s.bvh().size(), poison());
    std::atomic<std::size_t> leaf_calls{0};
    plan.run(s.bvh(), got, [&](std::uint32_t n) {
      ++leaf_calls;
      return s.leaf_volume(n, f);
    });
    EXPECT_TRUE(same_volumes(got, want)) << "step " << f;
    EXPECT_EQ(leaf_calls.load(), s.leaves().size()) << "step " << f << ": each leaf once";
    EXPECT_EQ(plan.nodes_refitted(s.bvh()), s.bvh().size());
  }
}

}  // namespace

TEST(RefitPlan, OneSubtreeMatchesSerialMerge) {
  BvttScene s(make_folding_cloth(4, 4), 1);  // 32 triangles, 63 nodes: under the default min_subtree
  const RefitPlan plan(s.bvh(), [](std::uint32_t) { return false; });
  ASSERT_EQ(plan.num_subtrees(), 1u);
  expect_run_matches_reference(s, plan);
}

TEST(RefitPlan, ManySubtreesMatchesSerialMerge) {
  BvttScene s(make_folding_cloth(24, 4), 1);  // 1,152 triangles, 2,303 nodes
  for (std::uint32_t min_subtree : {1u, 8u, 37u}) {
    const RefitPlan plan(s.bvh(), [](std::uint32_t) { return false; }, min_subtree);
    ASSERT_GT(plan.num_subtrees(), 16u) << "min_subtree " << min_subtree;
    SCOPED_TRACE("min_subtree " + std::to_string(min_subtree));
    expect_run_matches_reference(s, plan);
  }
}

TEST(RefitPlan, ManySubtreesMatchesSerialMergeInArenas) {
  BvttScene s(make_deforming_spheres(4, 8, 3), 2);  // 4 meshes: each its own subtree below a top
  const RefitPlan plan(s.bvh(), [](std::uint32_t) { return false; }, 4);
  ASSERT_GT(plan.num_subtrees(), 8u);
  for (int threads : {1, 3}) {
    tbb::task_arena arena(threads);
    SCOPED_TRACE(std::to_string(threads) + " threads");
    arena.execute([&] { expect_run_matches_reference(s, plan); });
  }
}

TEST(RefitPlan, SubtreesCoverEveryNodeOnce) {
  // The subtrees and the top partition the nodes: a leaf callback per leaf, and no node left
  // at its poisoned value (checked above); here: mixed nodes (above the meshes) are all in
  // the top, so no subtree spans two meshes.
  BvttScene s(make_deforming_spheres(3, 6, 2), 1);
  const RefitPlan plan(s.bvh(), [](std::uint32_t) { return false; }, 1u << 20);
  // A huge min_subtree would make the root one subtree, but the root spans meshes.
  EXPECT_GE(plan.num_subtrees(), 3u);
  std::set<std::uint32_t> meshes_seen;
  std::mutex m;
  LargeVector<NodeVolume> got(s.bvh().size(), poison());
  plan.run(s.bvh(), got, [&](std::uint32_t n) {
    std::lock_guard<std::mutex> lock(m);
    meshes_seen.insert(s.bvh().mesh_of_node(n));
    return s.leaf_volume(n, 0);
  });
  EXPECT_EQ(meshes_seen.size(), 3u);
  LargeVector<NodeVolume> want;
  s.reference_volumes(0, want);
  EXPECT_TRUE(same_volumes(got, want));
}

TEST(RefitPlan, StaticSubtreesRefittedOnceThenLeftAlone) {
  // Mesh 1 is static: run_static() refits its subtree from the initial volumes once; run()
  // never calls back for its leaves and never writes its nodes, and refits the rest (the top
  // included) every step from the current volumes.
  const AnimatedScene a = make_deforming_spheres(3, 8, 4);
  for (std::uint32_t min_subtree : {2048u, 4u}) {
    SCOPED_TRACE("min_subtree " + std::to_string(min_subtree));
    BvttScene s(a, 1);
    const BvhTopology& bvh = s.bvh();
    auto is_static = [&](std::uint32_t n) { return bvh.mesh_of_node(n) == 1; };
    const RefitPlan plan(bvh, is_static, min_subtree);
    LargeVector<NodeVolume> got(bvh.size(), poison());
    plan.run_static(bvh, got, [&](std::uint32_t n) {
      EXPECT_TRUE(is_static(n)) << "run_static() refitted moving leaf " << n;
      return s.leaf_volume(n, 0);
    });
    std::size_t static_nodes = 0;
    for (std::uint32_t n = 0; n < bvh.size(); ++n) static_nodes += is_static(n);
    ASSERT_GT(static_nodes, 0u);
    EXPECT_EQ(plan.nodes_refitted(bvh), bvh.size() - static_nodes);
    for (std::size_t f = 0; f < s.steps(); ++f) {
      std::atomic<int> static_calls{0};
      plan.run(bvh, got, [&](std::uint32_t n) {
        if (is_static(n)) ++static_calls;
        return s.leaf_volume(n, f);
      });
      EXPECT_EQ(static_calls.load(), 0) << "step " << f << ": run() refitted a static leaf";
      // The reference: static leaves at step 0, the others at step f, merged recursively.
      LargeVector<NodeVolume> at_f, at_0;
      s.reference_volumes(f, at_f);
      s.reference_volumes(0, at_0);
      LargeVector<NodeVolume> want(bvh.size());
      for (std::uint32_t n = bvh.size(); n-- > 0;) {
        if (is_static(n))
          want[n] = at_0[n];
        else if (bvh.leaf(n))
          want[n] = at_f[n];
        else
          want[n] = NodeVolume::merged(want[bvh.left(n)], want[bvh.right(n)]);
      }
      EXPECT_TRUE(same_volumes(got, want)) << "step " << f;
    }
  }
}
