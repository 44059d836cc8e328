// The BVTT walk (core/bvtt.h) against brute force over the BVH's leaves: a serial traversal
// from the root processes exactly the leaf pairs whose node volumes overlap (each once, with
// the quarters in which they overlap), and the front it records is a cut of the BVTT where
// every node is a leaf pair or a disjoint pair. Built directly over a generated scene's BVH
// with volumes and a leaf handler of the test's own (tests/support/bvtt_fixture.h).
#include <gtest/gtest.h>

#include <set>

#include "fixtures/scenes.h"
#include "support/bvtt_fixture.h"

using namespace mccd;
using namespace mccd::detail;
using test::BvttScene;
using test::LeafPairHit;

namespace {

/// A traversal from the root, as the `traverse` method runs it.
WorkerOutput traverse_from_root(const BvttScene& s, bool record) {
  WorkerOutput out;
  out.stack.push_back({0, 0});
  if (record)
    s.bvtt().traverse<true>(out);
  else
    s.bvtt().traverse<false>(out);
  return out;
}

::testing::AssertionResult same_hits(const std::vector<LeafPairHit>& got, const std::vector<LeafPairHit>& want) {
  if (got == want) return ::testing::AssertionSuccess();
  auto r = ::testing::AssertionFailure() << got.size() << " leaf pairs processed, " << want.size() << " expected";
  for (std::size_t i = 0; i < std::max(got.size(), want.size()); ++i)
    if (i >= got.size() || i >= want.size() || !(got[i] == want[i])) {
      r << "; first difference at " << i << ": got " << (i < got.size() ? test::describe(got[i]) : "-")
        << ", expected " << (i < want.size() ? test::describe(want[i]) : "-");
      break;
    }
  return r;
}

/// Every step of `s`: the traversal against brute force, its front a cut that stops now.
void expect_traversal_matches_brute_force(BvttScene& s, std::size_t min_hits) {
  std::size_t total = 0;
  for (std::size_t f = 0; f < s.steps(); ++f) {
    s.set_step(f);
    const std::vector<LeafPairHit> want = s.brute_force_pairs();
    const WorkerOutput rec = traverse_from_root(s, true);
    EXPECT_TRUE(same_hits(test::hits(rec.contacts), want)) << "step " << f << " (record)";
    EXPECT_TRUE(s.is_cut(rec.front, /*stops_now=*/true)) << "step " << f;
    // Every leaf pair of the front is one the traversal tested; the processed ones among them.
    std::size_t front_leaf_pairs = 0;
    for (const NodePair& n : rec.front) front_leaf_pairs += s.bvh().leaf(n.a) && s.bvh().leaf(n.b);
    EXPECT_GE(front_leaf_pairs, want.size()) << "step " << f;
    // A volume test at every pair node visited: each front node once, each expanded one once.
    EXPECT_GE(rec.stats.volume_tests, rec.front.size()) << "step " << f;

    const WorkerOutput plain = traverse_from_root(s, false);
    EXPECT_TRUE(plain.front.empty()) << "step " << f << ": recorded without `record`";
    EXPECT_TRUE(same_hits(test::hits(plain.contacts), want)) << "step " << f << " (no record)";
    EXPECT_EQ(plain.stats.volume_tests, rec.stats.volume_tests) << "step " << f;
    EXPECT_TRUE(plain.stack.empty());
    total += want.size();
  }
  EXPECT_GE(total, min_hits) << "the scene should bring leaves into contact";
}

}  // namespace

TEST(BvttTraversal, FoldingClothOneTriangleLeavesMatchesBruteForce) {
  BvttScene s(make_folding_cloth(14, 6), 1);  // 392 triangles, 5 steps
  expect_traversal_matches_brute_force(s, 100);
}

TEST(BvttTraversal, DeformingSpheresLargeLeavesMatchesBruteForce) {
  BvttScene s(make_deforming_spheres(3, 8, 6), 4);
  expect_traversal_matches_brute_force(s, 20);
}

TEST(BvttTraversal, RandomTrianglesMatchesBruteForce) {
  BvttScene s(make_random_triangles(400, 5, 7), 2);
  expect_traversal_matches_brute_force(s, 20);
}

TEST(BvttTraversal, LeafPairsTheLeafSkipsAreNeitherProcessedNorInTheFront) {
  BvttScene s(make_folding_cloth(12, 4), 1, {}, /*skip_mod=*/3);
  expect_traversal_matches_brute_force(s, 50);
}

TEST(BvttTraversal, PairsOfAMeshWithoutSelfCollisionAreSkipped) {
  // Mesh 1 is never tested against itself: no leaf pair inside it is processed or in the front.
  const AnimatedScene a = make_deforming_spheres(3, 8, 4);
  std::vector<MeshOptions> opts(a.meshes.size());
  opts[1].self_collision = false;
  BvttScene s(a, 2, opts);
  ASSERT_TRUE(s.topology().has_skipped_pairs());
  expect_traversal_matches_brute_force(s, 10);
  const WorkerOutput rec = traverse_from_root(s, true);
  for (const NodePair& n : rec.front)
    EXPECT_FALSE(s.bvh().mesh_of_node(n.a) == 1 && s.bvh().mesh_of_node(n.b) == 1)
        << "(" << n.a << ", " << n.b << ") inside mesh 1";
}

TEST(BvttTraversal, SelfNodeAndPairNodeChildren) {
  BvttScene s(make_folding_cloth(8, 2), 1);
  const BvhTopology& bvh = s.bvh();
  // A self node of an inner node: its children's pair, then both self nodes (the stack pops
  // (l, l) first).
  WorkerOutput out;
  std::vector<NodePair> next;
  s.bvtt().visit<true>({0, 0}, out, next);
  const std::uint32_t l = bvh.left(0), r = bvh.right(0);
  EXPECT_EQ(next, (std::vector<NodePair>{{l, r}, {r, r}, {l, l}}));
  EXPECT_TRUE(out.front.empty());
  EXPECT_EQ(out.stats.volume_tests, 0u);
  // A leaf's self node: nothing (the pairs inside one leaf are the self stage's).
  next.clear();
  s.bvtt().visit<true>({s.leaves()[0], s.leaves()[0]}, out, next);
  EXPECT_TRUE(next.empty());
  EXPECT_TRUE(out.front.empty());
  // push_children splits one side into its two children (right first: the stack pops the
  // left one first), never a leaf, and of two inner sides not the smaller (ties: a's).
  std::size_t checked = 0;
  for (std::uint32_t a = 0; a < bvh.size() && checked < 2000; a += 3)
    for (std::uint32_t b = bvh.nodes()[a].end; b < bvh.size() && checked < 2000; b += 7) {
      if (bvh.leaf(a) && bvh.leaf(b)) continue;
      std::vector<NodePair> ch;
      s.bvtt().push_children({a, b}, ch);
      ASSERT_EQ(ch.size(), 2u);
      const bool split_a = ch[0].b == b && ch[1].b == b;
      if (split_a) {
        EXPECT_EQ(ch[0].a, bvh.right(a));
        EXPECT_EQ(ch[1].a, bvh.left(a));
        EXPECT_FALSE(bvh.leaf(a));
        if (!bvh.leaf(b)) {
          EXPECT_GE(bvh.subtree_size(a), bvh.subtree_size(b)) << "(" << a << ", " << b << ")";
        }
      } else {
        EXPECT_EQ(ch[0], (NodePair{a, bvh.right(b)}));
        EXPECT_EQ(ch[1], (NodePair{a, bvh.left(b)}));
        EXPECT_FALSE(bvh.leaf(b));
        if (!bvh.leaf(a)) {
          EXPECT_GT(bvh.subtree_size(b), bvh.subtree_size(a)) << "(" << a << ", " << b << ")";
        }
      }
      ++checked;
    }
  EXPECT_GT(checked, 100u);
}

TEST(BvttTraversal, StoppedQueryEndsTheTraversal) {
  // A FirstContact query that has its answer: traverse() empties the stack, visits nothing.
  BvttScene s(make_folding_cloth(10, 3), 1);
  QueryState q;
  q.reset(StepKind::FirstContact);
  q.found(0.5);
  test::RecordingLeaf leaf;
  const BvttScene::Bvtt stopped(s.bvh(), s.nodes(), s.topology(), leaf, q);
  WorkerOutput out;
  out.stack.push_back({0, 0});
  stopped.traverse<true>(out);
  EXPECT_TRUE(out.stack.empty());
  EXPECT_TRUE(out.front.empty());
  EXPECT_TRUE(out.contacts.empty());
  EXPECT_EQ(out.stats.volume_tests, 0u);
}

TEST(BvttTraversal, BudgetWeighsALeafPairByItsFeaturePairs) {
  // traverse()'s work: a node test 1, a leaf pair at least kLeafPairWork, and more for the
  // feature pairs it tested and queued (kPairsPerUnit tests a unit, a queued pair
  // WorkerOutput::kQueuedPairWork tests), so that a task holding costly leaf pairs splits sooner
  BvttScene s(make_folding_cloth(12, 3), 1);
  using B = BvttScene::Bvtt;
  auto work_with = [&](std::uint64_t tested, std::size_t queued, std::size_t* processed) {
    test::RecordingLeaf leaf;
    leaf.tested_per_pair = tested;
    leaf.queued_per_pair = queued;
    QueryState q;
    q.reset(StepKind::Full);
    const B bvtt(s.bvh(), s.nodes(), s.topology(), leaf, q);
    WorkerOutput out;
    out.stack.push_back({0, 0});
    const std::size_t work = bvtt.traverse<false>(out);
    *processed = out.contacts.size();
    return work;
  };
  std::size_t plain_pairs = 0, tested_pairs = 0, queued_pairs = 0;
  const std::size_t plain = work_with(0, 0, &plain_pairs);
  const std::size_t tested = work_with(100 * B::kPairsPerUnit, 0, &tested_pairs);
  const std::size_t queued = work_with(0, 100, &queued_pairs);
  ASSERT_GT(plain_pairs, 0u);
  EXPECT_EQ(tested_pairs, plain_pairs);
  EXPECT_EQ(queued_pairs, plain_pairs);
  // each processed leaf pair: kLeafPairWork at first, then 100 units, then 100 x 9 / 8 units
  EXPECT_EQ(tested - plain, plain_pairs * (100 - B::kLeafPairWork));
  EXPECT_EQ(queued - plain, plain_pairs * (100 * WorkerOutput::kQueuedPairWork / B::kPairsPerUnit - B::kLeafPairWork));
  // a few tests a pair stay within the least a leaf pair counts
  std::size_t few_pairs = 0;
  EXPECT_EQ(work_with(B::kPairsPerUnit, 1, &few_pairs), plain);
}
