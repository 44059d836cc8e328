// The queue entries of feature pairs (core/feature_tests.h): an edge-edge entry names the
// lower edge id first, its ends first, whichever edge the leaf pair's loop met first; a
// vertex-face entry keeps its order. Entries are built without branches (bit masks), so each
// order of each pair is checked against the plain rule.
#include <mccd/core/feature_tests.h>
#include <mccd/geometry/kdop.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>

using namespace mccd;
using namespace mccd::detail;

namespace {
using Tests = FeatureTests<Kdop18>;
}  // namespace

TEST(QueuedPairs, AnEdgeEdgeEntryNamesTheLowerEdgeFirst) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 10000; ++trial) {
    // ids over the whole 32-bit range (the high bits must not leak between the two words)
    const auto id = [&] { return static_cast<std::uint32_t>(trial % 3 ? rng() % 64 : rng()); };
    std::uint32_t a = id(), b = id();
    if (a == b) b = a ^ 1u;
    const Edge ea{id(), id()}, eb{id(), id()};
    const unsigned quarters = static_cast<unsigned>(rng() % 32);
    const std::uint32_t leaf_a = id(), leaf_b = id();
    const QueuedPair p = Tests::ee_entry(a, ea, b, eb, quarters, leaf_a, leaf_b);
    const bool a_first = a < b;
    const Edge& first = a_first ? ea : eb;
    const Edge& second = a_first ? eb : ea;
    ASSERT_EQ(p.a, std::min(a, b)) << "trial " << trial;
    ASSERT_EQ(p.b, std::max(a, b)) << "trial " << trial;
    ASSERT_EQ(p.ids[0], first[0]) << "trial " << trial;
    ASSERT_EQ(p.ids[1], first[1]) << "trial " << trial;
    ASSERT_EQ(p.ids[2], second[0]) << "trial " << trial;
    ASSERT_EQ(p.ids[3], second[1]) << "trial " << trial;
    ASSERT_EQ(p.leaf_a, leaf_a);
    ASSERT_EQ(p.leaf_b, leaf_b);
    ASSERT_EQ(p.kind, 1);
    ASSERT_EQ(p.quarters, quarters);
    // the same pair met the other way round gives the same entry but for the leaves
    const QueuedPair q = Tests::ee_entry(b, eb, a, ea, quarters, leaf_b, leaf_a);
    ASSERT_EQ(q.a, p.a);
    ASSERT_EQ(q.b, p.b);
    for (int k = 0; k < 4; ++k) ASSERT_EQ(q.ids[k], p.ids[k]) << "trial " << trial;
  }
}

TEST(QueuedPairs, AVertexFaceEntryKeepsTheVertexThenTheFace) {
  const QueuedPair p = Tests::vf_entry(7, Triangle{3, 9, 4}, 12, 0x15, 2, 5);
  EXPECT_EQ(p.ids[0], 7u);
  EXPECT_EQ(p.ids[1], 3u);
  EXPECT_EQ(p.ids[2], 9u);
  EXPECT_EQ(p.ids[3], 4u);
  EXPECT_EQ(p.a, 7u);
  EXPECT_EQ(p.b, 12u);
  EXPECT_EQ(p.leaf_a, 2u);
  EXPECT_EQ(p.leaf_b, 5u);
  EXPECT_EQ(p.kind, 0);
  EXPECT_EQ(p.quarters, 0x15);
}
