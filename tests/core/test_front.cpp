// The front's memory cap (SceneOptions::max_front_bytes): a front over the cap is dropped, not
// kept, so the memory held between steps stays under it, and contacts never change.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include <mccd/core/front.h>
#include <mccd/parallel/scene.h>

#include "fixtures/scenes.h"

using namespace mccd;

namespace {

/// Steps `s` with fbd under `cap` beside an uncapped scene; checks contacts step by step and
/// the cap. Returns how many steps kept their front and how many dropped it.
std::pair<int, int> step_capped(const AnimatedScene& s, std::size_t cap, std::uint64_t* largest_uncapped) {
  SceneOptions free_opt, capped_opt;
  capped_opt.max_front_bytes = cap;
  Scene free_scene(s.meshes, free_opt), capped(s.meshes, capped_opt);
  int kept = 0, dropped = 0;
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const std::vector<PositionsView> next(s.frames[f].begin(), s.frames[f].end());
    const StepResult a = free_scene.advance(next), b = capped.advance(next);
    EXPECT_EQ(a.contacts, b.contacts) << s.name << " step " << f;
    EXPECT_EQ(a.earliest_toi, b.earliest_toi) << s.name << " step " << f;
    EXPECT_LE(b.stats.front_bytes, cap) << s.name << " step " << f;
    if (b.stats.front_size == 0) {
      ++dropped;
      EXPECT_EQ(b.stats.front_bytes, 0u);
    } else {
      ++kept;
    }
    if (largest_uncapped) *largest_uncapped = std::max(*largest_uncapped, a.stats.front_bytes);
  }
  return {kept, dropped};
}

}  // namespace

TEST(FrontMemory, TinyCapDropsEveryFrontAndRebuildsEachStep) {
  const AnimatedScene s = make_folding_cloth(30, 21);
  SceneOptions o;
  o.max_front_bytes = 1;
  Scene capped(s.meshes, o);
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const StepResult r = capped.advance(std::vector<PositionsView>(s.frames[f].begin(), s.frames[f].end()));
    EXPECT_EQ(r.stats.front_size, 0u) << "step " << f;
    EXPECT_EQ(r.stats.front_bytes, 0u) << "step " << f;
    EXPECT_EQ(r.stats.rebuilds, 1u) << "step " << f;  // built from the root every step
  }
  const auto [kept, dropped] = step_capped(s, 1, nullptr);
  EXPECT_EQ(kept, 0);
  EXPECT_EQ(dropped, static_cast<int>(s.frames.size()) - 1);
}

TEST(FrontMemory, CapBetweenStepsKeepsSomeFrontsAndDropsOthers) {
  for (const AnimatedScene& s : {make_folding_cloth(30, 21), make_deforming_spheres(3, 16, 11)}) {
    std::uint64_t largest = 0;
    step_capped(s, ~std::size_t(0), &largest);  // uncapped: the largest front it holds
    ASSERT_GT(largest, 0u) << s.name;
    // Under the largest front, so the scene is driven into the cap at least once.
    const auto [kept, dropped] = step_capped(s, static_cast<std::size_t>(largest * 3 / 4), nullptr);
    EXPECT_GT(dropped, 0) << s.name;
  }
}

TEST(FrontMemory, NoCapIsTheDefault) {
  EXPECT_EQ(SceneOptions{}.max_front_bytes, 0u);
  const AnimatedScene s = make_folding_cloth(20, 6);
  Scene sc(s.meshes);
  const StepResult r = sc.advance(std::vector<PositionsView>(s.frames[1].begin(), s.frames[1].end()));
  EXPECT_GT(r.stats.front_size, 0u);
}

// BvttFront (core/front.h) on its own, against plain references: build() is a stable sort of
// the concatenated pieces by first node; advance() concatenates the blocks in order and asks
// for a rebuild exactly when S/L > sprout_ratio or B/L > invalid_ratio over the counts since
// the last build (equal does not); cap() releases everything over the cap and nothing at or
// under it; invalidate() and release().
namespace {

using mccd::detail::BvttFront;
using mccd::detail::NodePair;
using mccd::detail::WorkerOutput;
using mccd::detail::WorkerOutputs;

/// `n` pieces of random nodes (first nodes from a small range, so that many share one).
WorkerOutputs random_pieces(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  WorkerOutputs pieces(n);
  for (WorkerOutput& o : pieces) {
    const std::size_t len = rng() % 40;
    for (std::size_t i = 0; i < len; ++i) {
      const std::uint32_t a = rng() % 25;
      o.front.push_back({a, a + 1 + static_cast<std::uint32_t>(rng() % 1000)});
    }
  }
  return pieces;
}

std::vector<NodePair> concatenated(const WorkerOutputs& units, std::size_t n) {
  std::vector<NodePair> all;
  for (std::size_t i = 0; i < n; ++i) all.insert(all.end(), units[i].front.begin(), units[i].front.end());
  return all;
}

std::vector<NodePair> nodes_of(const BvttFront& f) { return {f.nodes().begin(), f.nodes().end()}; }

/// One block of `size` nodes reporting `sprouted` and `invalidated`.
WorkerOutputs block(std::size_t size, std::uint64_t sprouted, std::uint64_t invalidated) {
  WorkerOutputs b(1);
  for (std::size_t i = 0; i < size; ++i) b[0].front.push_back({std::uint32_t(i), std::uint32_t(i + 1)});
  b[0].stats.sprouted = sprouted;
  b[0].stats.invalidated = invalidated;
  return b;
}

/// A built front (from one piece of `size` nodes).
BvttFront built(std::size_t size) {
  BvttFront f;
  WorkerOutputs p = block(size, 0, 0);
  f.build(p);
  return f;
}

}  // namespace

TEST(BvttFront, BuildIsAStableSortOfThePiecesByFirstNode) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    WorkerOutputs pieces = random_pieces(1 + seed % 7, seed);
    std::vector<NodePair> want = concatenated(pieces, pieces.size());
    std::stable_sort(want.begin(), want.end(), [](const NodePair& x, const NodePair& y) { return x.a < y.a; });
    BvttFront f;
    EXPECT_TRUE(f.needs_build());
    f.build(pieces);
    EXPECT_EQ(nodes_of(f), want) << "seed " << seed;
    EXPECT_EQ(f.size(), want.size());
    EXPECT_FALSE(f.needs_build());
    for (const WorkerOutput& o : pieces) {
      EXPECT_TRUE(o.front.empty());
      EXPECT_EQ(o.front.capacity(), 0u) << "a piece was not released";
    }
  }
}

// The traversal's costly leaf pairs (noted in its pieces) follow their nodes through the
// build's sort: the cuts end a block right after each, and the rest of the work is spread.
TEST(BvttFront, BuildCutsAtTheTraversalsCostlyLeafPairs) {
  for (unsigned seed = 1; seed <= 10; ++seed) {
    WorkerOutputs pieces = random_pieces(4, seed);
    std::vector<NodePair> costly_nodes;
    for (WorkerOutput& o : pieces) {
      o.stats.feature_box_tests = 1000;
      if (o.front.size() < 3) continue;
      const std::uint32_t at = static_cast<std::uint32_t>(o.front.size() / 2);
      o.costly.push_back({at, 1000000});
      o.stats.feature_box_tests += 1000000;
      costly_nodes.push_back(o.front[at]);
    }
    BvttFront f;
    f.set_block_nodes(4);  // many blocks: each costly node is several blocks' work
    f.build(pieces);
    const std::vector<std::uint32_t>& cuts = f.cuts();
    ASSERT_GE(cuts.size(), 2u) << "seed " << seed;
    EXPECT_EQ(cuts.front(), 0u);
    EXPECT_EQ(cuts.back(), f.size());
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      EXPECT_LT(cuts[k], cuts[k + 1]);
      EXPECT_LE(cuts[k + 1] - cuts[k], 4u * 4);
    }
    // each costly node ends its block: a cut right after it (its place in the sorted front;
    // random_pieces' nodes are unique with high probability: checked)
    for (const NodePair& c : costly_nodes) {
      const auto at = std::find(f.nodes().begin(), f.nodes().end(), c) - f.nodes().begin();
      ASSERT_EQ(std::count(f.nodes().begin(), f.nodes().end(), c), 1) << "seed " << seed;
      EXPECT_NE(std::find(cuts.begin(), cuts.end(), static_cast<std::uint32_t>(at + 1)), cuts.end())
          << "seed " << seed << ": no cut right after the costly node at " << at;
    }
  }
}

TEST(BvttFront, BuildOfNothingIsAnEmptyValidFront) {
  WorkerOutputs none(3);
  BvttFront f;
  f.build(none);
  EXPECT_EQ(f.size(), 0u);
  EXPECT_FALSE(f.needs_build());
}

TEST(BvttFront, AdvanceConcatenatesTheFirstBlocksInOrder) {
  BvttFront f = built(5);
  WorkerOutputs blocks = random_pieces(6, 99);
  blocks[5].front.push_back({7, 8});  // past num_blocks: ignored
  f.advance(blocks, 5, 1e9, 1e9);
  EXPECT_EQ(nodes_of(f), concatenated(blocks, 5));
  EXPECT_FALSE(f.needs_build());
  // And again, from the front just made (its buffers swapped, not shared).
  WorkerOutputs again = random_pieces(3, 7);
  f.advance(again, 3, 1e9, 1e9);
  EXPECT_EQ(nodes_of(f), concatenated(again, 3));
}

TEST(BvttFront, RebuildRuleSproutRatioEqualDoesNotTrigger) {
  // L = 10, sprout ratio 0.5: S = 5 keeps the front, S = 6 rebuilds.
  BvttFront f = built(10);
  f.advance(block(10, 5, 0), 1, 0.5, 1e9);
  EXPECT_FALSE(f.needs_build()) << "S/L == ratio must not trigger";
  BvttFront g = built(10);
  g.advance(block(10, 6, 0), 1, 0.5, 1e9);
  EXPECT_TRUE(g.needs_build()) << "S/L > ratio must trigger";
}

TEST(BvttFront, RebuildRuleInvalidRatioEqualDoesNotTrigger) {
  // L = 20, invalid ratio 0.25: B = 5 keeps the front, B = 6 rebuilds.
  BvttFront f = built(20);
  f.advance(block(20, 0, 5), 1, 1e9, 0.25);
  EXPECT_FALSE(f.needs_build()) << "B/L == ratio must not trigger";
  BvttFront g = built(20);
  g.advance(block(20, 0, 6), 1, 1e9, 0.25);
  EXPECT_TRUE(g.needs_build()) << "B/L > ratio must trigger";
}

TEST(BvttFront, RebuildRuleCountsSinceTheLastBuildOverTheNewSize) {
  // S accumulates over advances: 3 + 3 > 0.5 * 10 on the second.
  BvttFront f = built(10);
  f.advance(block(10, 3, 0), 1, 0.5, 1e9);
  EXPECT_FALSE(f.needs_build());
  f.advance(block(10, 3, 0), 1, 0.5, 1e9);
  EXPECT_TRUE(f.needs_build());
  // A build resets the counts.
  WorkerOutputs p = block(10, 0, 0);
  f.build(p);
  f.advance(block(10, 3, 0), 1, 0.5, 1e9);
  EXPECT_FALSE(f.needs_build()) << "counts from before the build were kept";
  // L is the new front's size: 4 nodes from a front of 10, S = 3 > 0.5 * 4.
  BvttFront g = built(10);
  g.advance(block(4, 3, 0), 1, 0.5, 1e9);
  EXPECT_TRUE(g.needs_build());
  // Both counts over all blocks: 2 + 2 + 2 = 6 > 0.5 * 10 only together.
  BvttFront h = built(10);
  WorkerOutputs three(3);
  for (std::size_t b = 0; b < 3; ++b) {
    for (std::uint32_t i = 0; i < (b == 0 ? 4u : 3u); ++i) three[b].front.push_back({i, i + 1});
    three[b].stats.invalidated = 2;
  }
  h.advance(three, 3, 1e9, 0.5);
  EXPECT_EQ(h.size(), 10u);
  EXPECT_TRUE(h.needs_build());
  BvttFront k = built(10);
  k.advance(three, 2, 1e9, 0.5);  // the first two blocks: 4 over 7 nodes, 4 > 3.5
  EXPECT_TRUE(k.needs_build());
  BvttFront m = built(10);
  m.advance(three, 1, 1e9, 0.5);  // the first block: 2 over 4 nodes, equal
  EXPECT_FALSE(m.needs_build());
}

TEST(BvttFront, RebuildRuleEmptyFrontCountsAsOne) {
  BvttFront f = built(3);
  f.advance(block(0, 1, 0), 1, 1.0, 1e9);  // S = 1, L = max(0, 1): equal, kept
  EXPECT_FALSE(f.needs_build());
  f.advance(block(0, 1, 0), 1, 1.0, 1e9);  // S = 2 > 1
  EXPECT_TRUE(f.needs_build());
}

TEST(BvttFront, CapReleasesOverTheCapAndKeepsAtOrUnderIt) {
  auto make = [](BvttFront& f, WorkerOutputs& units) {
    WorkerOutputs p = block(100, 0, 0);
    f.build(p);
    units = random_pieces(4, 3);
    for (WorkerOutput& o : units) o.front.reserve(64);
  };
  BvttFront f;
  WorkerOutputs units;
  make(f, units);
  std::size_t held = f.bytes();
  for (const WorkerOutput& o : units) held += o.front.capacity() * sizeof(NodePair);
  ASSERT_GT(held, f.bytes());
  // No cap.
  EXPECT_EQ(f.cap(units, 0), held);
  EXPECT_FALSE(f.needs_build());
  // At the cap: kept.
  EXPECT_EQ(f.cap(units, held), held);
  EXPECT_FALSE(f.needs_build());
  EXPECT_EQ(f.size(), 100u);
  EXPECT_EQ(f.cap(units, held + 1000), held);
  EXPECT_EQ(f.size(), 100u);
  // One byte over: everything released, the next step rebuilds.
  EXPECT_EQ(f.cap(units, held - 1), 0u);
  EXPECT_TRUE(f.needs_build());
  EXPECT_EQ(f.size(), 0u);
  EXPECT_EQ(f.bytes(), 0u);
  for (const WorkerOutput& o : units) EXPECT_EQ(o.front.capacity(), 0u);
}

TEST(BvttFront, InvalidateKeepsTheNodesReleaseDropsThem) {
  BvttFront f = built(50);
  f.invalidate();
  EXPECT_TRUE(f.needs_build());
  EXPECT_EQ(f.size(), 50u) << "invalidate() only marks the front";
  EXPECT_GT(f.bytes(), 0u);
  BvttFront g = built(50);
  g.advance(block(30, 0, 0), 1, 1e9, 1e9);  // both buffers in use
  g.release();
  EXPECT_TRUE(g.needs_build());
  EXPECT_EQ(g.size(), 0u);
  EXPECT_EQ(g.bytes(), 0u);
  // A released front builds again.
  WorkerOutputs p = block(7, 0, 0);
  g.build(p);
  EXPECT_EQ(g.size(), 7u);
  EXPECT_FALSE(g.needs_build());
}

// The cuts of the next tracking: blocks of about equal work by the last step's counts, in
// order, covering the front once, none longer than 4 block sizes; none after a build.
TEST(BvttFront, CutsSplitTheCostlyPartsIntoMoreBlocks) {
  BvttFront f = built(10);
  ASSERT_GE(f.cuts().size(), 2u) << "a built front is cut too";
  EXPECT_EQ(f.cuts().front(), 0u);
  EXPECT_EQ(f.cuts().back(), 10u);
  // 8 parts of 200 nodes; part 2 did 50 times the work of the others
  WorkerOutputs parts(8);
  for (std::size_t b = 0; b < parts.size(); ++b) {
    for (std::uint32_t i = 0; i < 200; ++i) parts[b].front.push_back({std::uint32_t(b), 1000 + i});
    parts[b].stats.volume_tests = 200;
    parts[b].stats.feature_box_tests = b == 2 ? 500000 : 10000;
  }
  f.set_block_nodes(64);
  f.advance(parts, parts.size(), 1e9, 1e9);
  const std::vector<std::uint32_t>& cuts = f.cuts();
  ASSERT_GE(cuts.size(), 2u);
  EXPECT_EQ(cuts.front(), 0u);
  EXPECT_EQ(cuts.back(), f.size());
  std::vector<double> work;  // each block's share of the parts' work, spread evenly on their nodes
  std::size_t in_costly = 0;
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    ASSERT_LT(cuts[k], cuts[k + 1]) << "block " << k;
    EXPECT_LE(cuts[k + 1] - cuts[k], 4u * 64) << "block " << k;
    double w = 0;
    for (std::uint32_t i = cuts[k]; i < cuts[k + 1]; ++i) {
      const std::size_t b = i / 200;
      w += BvttFront::work_of(parts[b].stats) / 200 + BvttFront::kNodeWork;
    }
    work.push_back(w);
    if (cuts[k] >= 400 && cuts[k + 1] <= 600) ++in_costly;
  }
  // as many blocks as fixed blocks of 64 would give (25), within a few
  EXPECT_NEAR(double(work.size()), 25.0, 3.0);
  // the costly part holds most of the work, so most of the blocks
  EXPECT_GE(in_costly, 12u);
  const double largest = *std::max_element(work.begin(), work.end());
  const double mean = std::accumulate(work.begin(), work.end(), 0.0) / double(work.size());
  EXPECT_LE(largest, 1.5 * mean);
  // fixed blocks of 64 would have put 64 of the costly nodes in a block: 4x the mean and more
  double fixed_largest = 0;
  for (std::size_t lo = 0; lo < f.size(); lo += 64) {
    double w = 0;
    for (std::size_t i = lo; i < std::min<std::size_t>(f.size(), lo + 64); ++i)
      w += BvttFront::work_of(parts[i / 200].stats) / 200 + BvttFront::kNodeWork;
    fixed_largest = std::max(fixed_largest, w);
  }
  EXPECT_GT(fixed_largest, 3 * largest);
  // forgotten with the front
  f.invalidate();
  EXPECT_TRUE(f.cuts().empty());
}

// A small front gets smaller blocks, down to the least size, so that it still gives many; a
// large one keeps the largest size. The cuts give as many blocks as that size would.
TEST(BvttFront, SmallFrontsGetSmallerBlocks) {
  BvttFront f = built(10);
  f.set_block_nodes(64, 16, 128);
  EXPECT_EQ(f.block_size(100000), 64u);
  EXPECT_EQ(f.block_size(128 * 64), 64u);
  EXPECT_EQ(f.block_size(128 * 40), 40u);
  EXPECT_EQ(f.block_size(1000), 16u);
  EXPECT_EQ(f.block_size(0), 16u);
  // one size only: the old fixed rule
  BvttFront g = built(10);
  g.set_block_nodes(32);
  EXPECT_EQ(g.block_size(10), 32u);
  EXPECT_EQ(g.block_size(1000000), 32u);
  // 4 parts of 800 nodes of equal work: 3200 nodes in blocks of 25, about 128 of them
  WorkerOutputs parts(4);
  for (std::size_t b = 0; b < parts.size(); ++b) {
    for (std::uint32_t i = 0; i < 800; ++i) parts[b].front.push_back({std::uint32_t(b), 1000 + i});
    parts[b].stats.feature_box_tests = 5000;
  }
  f.advance(parts, parts.size(), 1e9, 1e9);
  ASSERT_EQ(f.size(), 3200u);
  EXPECT_EQ(f.block_size(f.size()), 25u);
  const std::vector<std::uint32_t>& cuts = f.cuts();
  ASSERT_GE(cuts.size(), 2u);
  EXPECT_NEAR(double(cuts.size() - 1), 128.0, 3.0);
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) EXPECT_LE(cuts[k + 1] - cuts[k], 4u * 25) << "block " << k;
}

// A costly node (a leaf pair noted by track()) weighs where it lies, not spread over its part:
// its block ends with it.
TEST(BvttFront, CutsEndABlockAtACostlyNode) {
  BvttFront f = built(10);
  WorkerOutputs parts(4);
  for (std::size_t b = 0; b < parts.size(); ++b) {
    for (std::uint32_t i = 0; i < 100; ++i) parts[b].front.push_back({std::uint32_t(b), 1000 + i});
    parts[b].stats.feature_box_tests = 2000;
  }
  parts[2].costly.push_back({37, 100000});
  parts[2].stats.feature_box_tests += 100000;
  f.set_block_nodes(16);
  f.advance(parts, parts.size(), 1e9, 1e9);
  const std::vector<std::uint32_t>& cuts = f.cuts();
  ASSERT_GE(cuts.size(), 2u);
  EXPECT_EQ(cuts.back(), 400u);
  EXPECT_NE(std::find(cuts.begin(), cuts.end(), 2 * 100 + 37 + 1), cuts.end()) << "no cut right after the costly node";
  // the rest of its part is as light as the other parts: a few cuts there (its work spread
  // evenly over the part would have cut it into many small blocks)
  const auto in_part = std::count_if(cuts.begin(), cuts.end(), [](std::uint32_t c) { return c > 200 && c < 300; });
  EXPECT_LE(in_part, 3);
}
