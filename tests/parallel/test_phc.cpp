// PHC (parallel/phc.h): traverse_phc, the BVTT's top expanded breadth-first into tasks that
// run in parallel, processes the same leaf pairs and records the same front (as a set) as the
// serial traversal from the root, for any number of tasks: 1, 4, 64, the default and more
// tasks than the top ever has (everything in the serial top); with and without recording; and
// for any budget of work a task has before the rest of its stack is split off into tasks of
// their own (1, 7, the default, unlimited); and for any budget of work of the serial top (the
// default and unlimited; 1 and 64 with the default number of tasks).
#include <type_traits>

#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <mccd/parallel/phc.h>

#include "fixtures/scenes.h"
#include "support/bvtt_fixture.h"

using namespace mccd;
using namespace mccd::detail;
using test::BvttScene;

namespace {

constexpr std::size_t kMinTasks[] = {1, 4, 64, 0 /* phc_tasks() */, std::size_t(1) << 30};
constexpr std::size_t kUnlimited = static_cast<std::size_t>(-1);
constexpr std::size_t kWorkBudgets[] = {1, 7, kTaskWork, kUnlimited};
constexpr std::size_t kTopBudgets[] = {1, 64, kTopWork, kUnlimited};

std::vector<NodePair> all_fronts(const WorkerOutputs& outs) {
  std::vector<NodePair> all;
  for (const WorkerOutput& o : outs) all.insert(all.end(), o.front.begin(), o.front.end());
  return test::sorted(std::move(all));
}

template <bool record>
void expect_phc_equals_serial(const BvttScene& s, const char* what) {
  WorkerOutput serial;
  ContactBuffer serial_contacts;
  traverse_serial<record>(s.bvtt(), serial, serial_contacts);
  const auto want_hits = test::hits(serial_contacts);
  const auto want_front = test::sorted(serial.front);
  ASSERT_FALSE(want_hits.empty()) << what;
  if (record) {
    ASSERT_FALSE(want_front.empty()) << what;
  }
  auto text = [](std::size_t n) { return n == kUnlimited ? std::string("unlimited") : std::to_string(n); };
  for (std::size_t min_tasks : kMinTasks)
    for (std::size_t visits : kWorkBudgets)
      for (std::size_t top : kTopBudgets) {
        // The small budgets of the top with the default number of tasks only (the test's time).
        if (top < kTopWork && min_tasks != 0) continue;
        SCOPED_TRACE(std::string(what) + ", min_tasks " + std::to_string(min_tasks) + ", work " + text(visits) +
                     ", top work " + text(top) + (record ? ", record" : ""));
        WorkerOutputs outs;
        ContactBuffer contacts;
        traverse_phc<record>(s.bvtt(), outs, contacts, min_tasks, visits, top);
        EXPECT_EQ(test::hits(contacts), want_hits);
        EXPECT_EQ(all_fronts(outs), want_front);
        std::uint64_t volume_tests = 0;
        for (const WorkerOutput& o : outs) {
          volume_tests += o.stats.volume_tests;
          EXPECT_TRUE(o.stack.empty()) << "a task left nodes unvisited";
        }
        EXPECT_EQ(volume_tests, serial.stats.volume_tests) << "the same node tests";
        // The serial top stops within one visit of its budget: a node test, or a leaf pair.
        if (top != kUnlimited) {
          EXPECT_LE(outs[0].stats.volume_tests, top + std::remove_cvref_t<decltype(s.bvtt())>::kLeafPairWork);
        }
        const std::size_t want_tasks = min_tasks ? min_tasks : phc_tasks(s.bvh().size());
        if (want_tasks == 1) {
          EXPECT_EQ(outs.size(), 2u) << "one task: the root (with the parts it split off)";
        }
        if (want_tasks >= (std::size_t(1) << 30) && top == kUnlimited) {
          EXPECT_EQ(outs.size(), 1u) << "the top ran out of nodes";
        }
        // Otherwise at least min_tasks tasks, unless the top ran out of nodes first.
        if (want_tasks > 1 && want_tasks < (std::size_t(1) << 30) && top == kUnlimited) {
          EXPECT_TRUE(outs.size() >= 1 + want_tasks || outs.size() == 1) << outs.size() << " outputs";
        }
        // Reused outputs (the engine keeps them from step to step) give the same again.
        ContactBuffer again;
        traverse_phc<record>(s.bvtt(), outs, again, min_tasks, visits, top);
        EXPECT_EQ(test::hits(again), want_hits) << "second run";
        EXPECT_EQ(all_fronts(outs), want_front) << "second run";
      }
}

void expect_every_step(BvttScene& s, const char* what) {
  for (std::size_t f = 0; f < s.steps(); ++f) {
    s.set_step(f);
    SCOPED_TRACE("step " + std::to_string(f));
    expect_phc_equals_serial<true>(s, what);
    expect_phc_equals_serial<false>(s, what);
  }
}

}  // namespace

TEST(PhcTraversal, FoldingClothEqualsSerial) {
  BvttScene s(make_folding_cloth(16, 4), 1);
  expect_every_step(s, "cloth");
}

TEST(PhcTraversal, SpheresLargeLeavesEqualsSerial) {
  BvttScene s(make_deforming_spheres(3, 8, 3), 5);
  expect_every_step(s, "spheres");
}

TEST(PhcTraversal, WithSkippedPairsEqualsSerial) {
  const AnimatedScene a = make_deforming_spheres(3, 8, 2);
  std::vector<MeshOptions> opts(a.meshes.size());
  opts[0].self_collision = false;
  BvttScene s(a, 1, opts, /*skip_mod=*/4);
  expect_every_step(s, "skipped");
}

TEST(PhcTraversal, EqualsSerialInArenas) {
  BvttScene s(make_folding_cloth(16, 2), 1);
  for (int threads : {1, 2, 4}) {
    tbb::task_arena arena(threads);
    arena.execute([&] { expect_phc_equals_serial<true>(s, ("arena " + std::to_string(threads)).c_str()); });
  }
}

TEST(PhcTraversal, PhcTasksDependsOnlyOnTheBvhSize) {
  EXPECT_EQ(phc_tasks(0), 256u);
  EXPECT_EQ(phc_tasks(4 * 1000), 1000u);
  EXPECT_EQ(phc_tasks(1u << 30), 4096u);
}
