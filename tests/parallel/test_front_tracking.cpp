// Front tracking (parallel/front_tracking.h over BvttFront::track, core/front.h), against
// references:
//  - directly, over a BVTT of the test's own (tests/support/bvtt_fixture.h): a front built at
//    step 0 and then only tracked (never rebuilt) processes at every step exactly the leaf
//    pairs brute force finds; after tracking, the front is still a cut of the BVTT, every node
//    a stop for the current volumes, every node of the old front that stops now kept, the
//    blocks' parts joined in order (each block's part ending with the parts of the sprouts it
//    left past its budget of work, for budgets of 1 and 3 units and the default), and
//    L' = L - B + S; readonly
//    tracking processes the same pairs and leaves the front unchanged;
//  - through the stepper: fbd (never rebuilding, or with the default rule; both representative
//    rules) gives the contacts of a traversal from the root at every step; every front node
//    is valid (in range, a <= b); queries leave the front as it was.
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <random>
#include <set>

#include <mccd/parallel/front_tracking.h>
#include <mccd/parallel/phc.h>

#include "fixtures/scenes.h"
#include "support/bvtt_fixture.h"
#include "support/stepper_rig.h"

using namespace mccd;
using namespace mccd::detail;
using test::BvttScene;

namespace {

std::vector<NodePair> nodes_of(const BvttFront& f) { return {f.nodes().begin(), f.nodes().end()}; }

/// Builds the front at step 0 (PHC with recording, as fbd builds it), then tracks it through
/// every later step, checking each against the references. Returns the largest front seen.
/// `task_work`: each block's budget of sprout work (units of Bvtt::traverse; see
/// parallel/front_tracking.h); with `expect_left`, some step's front tracked as one block with
/// that budget must leave sprouts to be traversed apart.
std::size_t track_through(BvttScene& s, std::size_t task_work = kTaskWork, bool expect_left = false) {
  s.set_step(0);
  BvttFront front;
  WorkerOutputs units;
  ContactBuffer built_contacts;
  traverse_phc<true>(s.bvtt(), units, built_contacts);
  front.build(units);
  EXPECT_EQ(test::hits(built_contacts), s.brute_force_pairs()) << "build";
  EXPECT_TRUE(s.is_cut(nodes_of(front), true)) << "built front";
  std::size_t largest = front.size();
  std::uint64_t total_sprouted = 0;
  bool any_left = false;
  for (std::size_t f = 1; f < s.steps(); ++f) {
    SCOPED_TRACE("step " + std::to_string(f));
    s.set_step(f);
    const auto want = s.brute_force_pairs();
    const std::vector<NodePair> before = nodes_of(front);

    // Readonly (a query): the same pairs, nothing recorded, the front untouched.
    WorkerOutputs ro_blocks;
    ContactBuffer ro_contacts;
    const std::size_t ro_n = track_front(s.bvtt(), front, ro_blocks, ro_contacts, /*readonly=*/true, task_work);
    EXPECT_EQ(test::hits(ro_contacts), want) << "readonly";
    for (std::size_t b = 0; b < ro_n; ++b) EXPECT_TRUE(ro_blocks[b].front.empty()) << "readonly block " << b;
    EXPECT_EQ(nodes_of(front), before) << "readonly tracking changed the front";

    // Tracking: the pairs, then the next front.
    WorkerOutputs blocks;
    ContactBuffer contacts;
    WorkerOutput probe;  // the whole front as one block under the same budget
    BvttFront::track(s.bvtt(), front.nodes().data(), front.nodes().data() + front.size(), probe, task_work);
    any_left = any_left || !probe.left.empty();
    const std::vector<std::uint32_t> cuts = front.cuts();
    EXPECT_EQ(cuts.empty(), before.empty()) << "cut after the build and after every step that tracked";
    const std::size_t n = track_front(s.bvtt(), front, blocks, contacts, /*readonly=*/false, task_work);
    if (cuts.empty()) {
      const std::size_t block = front.block_size(before.size());
      EXPECT_EQ(n, (before.size() + block - 1) / block);
    } else {
      EXPECT_EQ(n, cuts.size() - 1);
      EXPECT_EQ(cuts.back(), before.size());
    }
    EXPECT_EQ(test::hits(contacts), want);
    std::vector<NodePair> joined;
    std::uint64_t sprouted = 0, invalidated = 0;
    for (std::size_t b = 0; b < n; ++b) {
      EXPECT_TRUE(blocks[b].stack.empty() && blocks[b].left.empty()) << "output " << b << " left nodes untraversed";
      joined.insert(joined.end(), blocks[b].front.begin(), blocks[b].front.end());
      sprouted += blocks[b].stats.sprouted;
      invalidated += blocks[b].stats.invalidated;
    }
    front.advance(blocks, n, 1e9, 1e9);  // never rebuilt: tracked at every step
    EXPECT_FALSE(front.needs_build());
    const std::vector<NodePair> after = nodes_of(front);
    EXPECT_EQ(after, joined) << "blocks joined out of order";
    EXPECT_EQ(after.size(), before.size() - invalidated + sprouted) << "L' = L - B + S";
    EXPECT_TRUE(s.is_cut(after, /*stops_now=*/true));
    // No pruning: every old node that stops now is kept.
    const std::set<NodePair> kept(after.begin(), after.end());
    for (const NodePair& p : before) {
      const bool stops = (s.bvh().leaf(p.a) && s.bvh().leaf(p.b)) || !s.bvtt().quarters(p);
      if (stops) {
        EXPECT_TRUE(kept.count(p)) << "(" << p.a << ", " << p.b << ") dropped";
      }
    }
    largest = std::max(largest, after.size());
    total_sprouted += sprouted;
  }
  EXPECT_GT(total_sprouted, 0u) << "the scene should make the front sprout";
  if (expect_left) {
    EXPECT_TRUE(any_left) << "no sprout went past the budget";
  }
  return largest;
}

}  // namespace

TEST(FrontTracking, TrackedFrontMatchesBruteForceAtEveryStep) {
  BvttScene s(make_folding_cloth(22, 8), 1);  // fronts of several blocks: tracked in parallel
  EXPECT_GT(track_through(s), kSerialBlocks * kFrontBlock);
}

TEST(FrontTracking, SproutsPastTheirBudgetAreTraversedApart) {
  BvttScene s(make_folding_cloth(22, 8), 1);
  for (std::size_t visits : {std::size_t(1), std::size_t(3)}) {
    SCOPED_TRACE(std::to_string(visits) + " units of work a block");
    track_through(s, visits, /*expect_left=*/true);
  }
}

// The build's counting sort in parallel chunks of pieces: the same front (a stable sort of the
// pieces' nodes by first node), the same costly places and cuts as on one thread, for fronts of
// one chunk and of many.
TEST(FrontTracking, BuildInParallelChunksIsTheStableSort) {
  for (std::size_t pieces_count : {std::size_t(3), std::size_t(40), std::size_t(900)}) {
    SCOPED_TRACE(std::to_string(pieces_count) + " pieces");
    auto make = [pieces_count] {  // the same pieces every time
      std::mt19937 rng(static_cast<unsigned>(pieces_count));
      WorkerOutputs pieces(pieces_count);
      for (WorkerOutput& o : pieces) {
        const std::size_t len = rng() % 200;
        for (std::size_t i = 0; i < len; ++i) {
          const std::uint32_t first = static_cast<std::uint32_t>(rng() % 3000);
          o.front.push_back({first, first + 1 + static_cast<std::uint32_t>(rng() % 100000)});
        }
        o.stats.feature_box_tests = rng() % 5000;
        if (len > 10) o.costly.push_back({static_cast<std::uint32_t>(len / 3), 1000000});
      }
      return pieces;
    };
    WorkerOutputs a = make(), b = make();
    std::vector<NodePair> want;
    for (const WorkerOutput& o : a) want.insert(want.end(), o.front.begin(), o.front.end());
    std::stable_sort(want.begin(), want.end(), [](const NodePair& x, const NodePair& y) { return x.a < y.a; });
    BvttFront serial, parallel;
    serial.set_block_nodes(16);
    parallel.set_block_nodes(16);
    serial.build(a, serial_executor());
    tbb::task_arena arena(4);
    arena.execute([&] { parallel.build(b, tbb_executor()); });
    EXPECT_EQ(nodes_of(serial), want);
    EXPECT_EQ(nodes_of(parallel), want);
    EXPECT_EQ(parallel.cuts(), serial.cuts());
  }
}

TEST(FrontTracking, SmallFrontTrackedSeriallyMatchesBruteForce) {
  BvttScene s(make_folding_cloth(5, 6), 1);
  EXPECT_LE(track_through(s), kSerialBlocks * kFrontBlock);
}

TEST(FrontTracking, LargeLeavesAndSkippedPairsMatchBruteForce) {
  const AnimatedScene a = make_deforming_spheres(4, 8, 6);
  std::vector<MeshOptions> opts(a.meshes.size());
  opts[2].self_collision = false;
  BvttScene s(a, 3, opts);
  track_through(s);
}

TEST(FrontTracking, TrackedFrontMatchesBruteForceInArenas) {
  BvttScene s(make_folding_cloth(22, 4), 1);
  for (int threads : {1, 3}) {
    tbb::task_arena arena(threads);
    SCOPED_TRACE(std::to_string(threads) + " threads");
    arena.execute([&] { track_through(s); });
  }
}

namespace {

/// fbd with `options` against a traversal from the root at every step; the front valid
/// after each; queries (first contact, earliest, candidates) leave it unchanged. Returns the
/// rebuilds after the first step.
template <BoundingVolume BV>
std::uint64_t expect_fbd_equals_traverse(const AnimatedScene& a, SceneOptions options, bool with_queries) {
  test::StepperRig<BV> fbd(a, options), trav(a, options);
  std::uint64_t rebuilds = 0, sprouted = 0;
  std::size_t contacts = 0;
  for (std::size_t f = 0; f < fbd.steps(); ++f) {
    SCOPED_TRACE(a.name + " step " + std::to_string(f));
    if (with_queries && f > 0) {
      const std::vector<NodePair> before = nodes_of(fbd.stepper().front());
      const bool needs_build = fbd.stepper().front().needs_build();
      for (StepKind k : {StepKind::FirstContact, StepKind::Earliest, StepKind::Candidates}) {
        fbd.step(f, Method::Fbd, k);
        EXPECT_EQ(nodes_of(fbd.stepper().front()), before) << "query " << int(k) << " changed the front";
        EXPECT_EQ(fbd.stepper().front().needs_build(), needs_build);
      }
    }
    const StepResult r = fbd.step(f, Method::Fbd), t = trav.step(f, Method::Traverse);
    if (r.contacts != t.contacts) {
      ADD_FAILURE() << "fbd: " << r.contacts.size() << " contacts, traverse: " << t.contacts.size();
      return rebuilds;
    }
    EXPECT_EQ(r.earliest_toi, t.earliest_toi);
    contacts += r.contacts.size();
    if (f == 0) {
      EXPECT_EQ(r.stats.rebuilds, 1u) << "the first step builds the front";
    }
    if (f > 0) rebuilds += r.stats.rebuilds;
    if (f > 0 && !r.stats.rebuilds) sprouted += r.stats.sprouted;
    const BvttFront& front = fbd.stepper().front();
    EXPECT_EQ(front.size(), r.stats.front_size);
    const std::size_t size = fbd.bvh_size();
    std::size_t bad = 0;
    for (const NodePair& n : front.nodes()) bad += !(n.a <= n.b && n.b < size);
    EXPECT_EQ(bad, 0u) << "front nodes out of range or unordered";
  }
  EXPECT_GT(contacts, 0u) << a.name;
  if (rebuilds + 1 < fbd.steps()) {
    EXPECT_GT(sprouted, 0u) << a.name << ": tracked steps should sprout";
  }
  return rebuilds;
}

SceneOptions never_rebuild() {
  SceneOptions o;
  o.rebuild_sprout_ratio = o.rebuild_invalid_ratio = 1e12;
  return o;
}

}  // namespace

TEST(FrontTracking, FbdNeverRebuildingEqualsTraverse) {
  const AnimatedScene cloth = make_folding_cloth(20, 12);
  EXPECT_EQ(expect_fbd_equals_traverse<Kdop18>(cloth, never_rebuild(), true), 0u);
  EXPECT_EQ(expect_fbd_equals_traverse<Aabb>(make_deforming_spheres(3, 8, 8), never_rebuild(), false), 0u);
}

TEST(FrontTracking, FbdMedianCanonicalNeverRebuildingEqualsTraverse) {
  // The paper's setting: one triangle a leaf, the canonical rule (no self culling).
  SceneOptions o = never_rebuild();
  o.bvh = BvhBuild::Median;
  o.representatives = Representatives::Canonical;
  EXPECT_EQ(expect_fbd_equals_traverse<Kdop18>(make_folding_cloth(16, 10), o, true), 0u);
}

TEST(FrontTracking, FbdDefaultRuleEqualsTraverse) {
  expect_fbd_equals_traverse<Kdop18>(make_twisting_tube(30, 16, 10), SceneOptions{}, true);
  SceneOptions tight;
  tight.rebuild_sprout_ratio = tight.rebuild_invalid_ratio = 1e-9;  // rebuilds whenever anything sprouts
  EXPECT_GT(expect_fbd_equals_traverse<Kdop18>(make_folding_cloth(16, 8), tight, false), 0u);
}
