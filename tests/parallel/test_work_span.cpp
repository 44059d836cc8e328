// Work and span of a step's stages (SceneOptions::work_span, parallel/tbb_executor.h): the
// same contacts as without; at one thread each stage's work is at most its own time and its
// span at most its work; through the flow graph the search and the self stage count as one
// branch whose span is the longer of theirs; off, nothing is measured; loops and invokes
// nested in a task add their own span to the task's, not their whole time.
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>

#include <mccd/parallel/scene.h>
#include <mccd/parallel/tbb_executor.h>

#include "fixtures/scenes.h"

using namespace mccd;

namespace {

std::vector<PositionsView> views(const std::vector<Positions>& frame) { return {frame.begin(), frame.end()}; }

void expect_consistent(const WorkSpan& ws, double stage_seconds, const char* what) {
  EXPECT_GE(ws.span, 0.0) << what;
  EXPECT_LE(ws.span, ws.work * (1 + 1e-9) + 1e-12) << what;
  // One thread runs the stage's tasks one after another inside its wall time: their sum and the
  // time between the loops never exceed it (counting a nested loop's tasks twice would).
  EXPECT_LE(ws.work, stage_seconds * (1 + 1e-9) + 1e-12) << what;
}

}  // namespace

TEST(WorkSpan, OneThreadWorkIsTheStageTimeAndContactsDoNotChange) {
  const AnimatedScene s = make_folding_cloth(40, 6);  // 3,200 triangles: the stages in sequence
  tbb::task_arena one(1);
  SceneOptions measured, plain;
  measured.work_span = true;
  measured.arena = plain.arena = &one;
  Scene a(s.meshes, measured), b(s.meshes, plain);
  double work = 0, wall = 0;
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const StepResult ra = a.advance(views(s.frames[f])), rb = b.advance(views(s.frames[f]));
    ASSERT_EQ(ra.contacts, rb.contacts) << "step " << f;
    const StepStats& st = ra.stats;
    expect_consistent(st.ws_update, st.t_update, "update");
    expect_consistent(st.ws_refit, st.t_refit, "refit");
    expect_consistent(st.ws_search, st.t_front, "search");
    expect_consistent(st.ws_self, st.t_self, "self");
    expect_consistent(st.ws_join, st.t_contacts, "join");
    EXPECT_GT(st.ws_search.work, 0.0);
    // in sequence, the branch's span is the sum of the two
    EXPECT_DOUBLE_EQ(st.ws_branch.work, st.ws_search.work + st.ws_self.work);
    EXPECT_DOUBLE_EQ(st.ws_branch.span, st.ws_search.span + st.ws_self.span);
    EXPECT_EQ(rb.stats.ws_search.work, 0.0);  // off: nothing measured
    EXPECT_EQ(rb.stats.ws_branch.span, 0.0);
    EXPECT_EQ(rb.stats.ws_input.work, 0.0);
    // the positions taken in: measured, inside the step's time, never a stage's
    EXPECT_GT(st.ws_input.work, 0.0);
    EXPECT_LE(st.ws_input.span, st.ws_input.work);
    EXPECT_LE(st.ws_input.work + st.ws_update.work + st.ws_refit.work + st.ws_branch.work + st.ws_join.work,
              st.t_total * (1 + 1e-9));
    // on one thread the prediction for one thread is the step's own time
    EXPECT_NEAR(st.predicted_seconds(1), st.t_total, 1e-9 + 1e-9 * st.t_total);
    EXPECT_LE(st.predicted_seconds(2), st.predicted_seconds(1) + 1e-12);
    work += st.ws_update.work + st.ws_refit.work + st.ws_search.work + st.ws_self.work + st.ws_join.work;
    wall += st.t_update + st.t_refit + st.t_front + st.t_self + st.t_contacts;
  }
  // From below, only over all steps together: the time between a loop's tasks (the scheduler's,
  // and any stall of a busy machine there) is no task's, so a single short stage can fall well
  // short of its wall time; all of them together cover most of it when every task is counted.
  EXPECT_GE(work, 0.5 * wall);
}

TEST(WorkSpan, FlowGraphBranchSpanIsTheLongerOfSearchAndSelf) {
  const AnimatedScene s = make_folding_cloth(70, 3);  // 9,800 triangles: through the flow graph
  SceneOptions measured;
  measured.work_span = true;
  Scene a(s.meshes, measured);
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const StepStats st = a.advance(views(s.frames[f])).stats;
    EXPECT_DOUBLE_EQ(st.ws_branch.span, std::max(st.ws_search.span, st.ws_self.span)) << "step " << f;
    EXPECT_GE(st.ws_search.work, st.ws_search.span);
    // every task of a loop is at most the loop: the span never exceeds the stage's wall time
    EXPECT_LE(st.ws_search.span, st.t_front * 1.2 + 2e-4);
    // 5,041 vertices taken in as three chunks: work beyond the span (each chunk a task)
    EXPECT_LT(st.ws_input.span, st.ws_input.work) << "step " << f;
  }
}

namespace {

/// Busy for about `seconds` (a task of known length; a stall of the machine only adds).
void spin(double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
  }
}

}  // namespace

// A loop inside a loop's task, and a recursive invoke: the span follows the longest path
// through the nested loops (what a greedy scheduler could reach), not the outer task whole.
// Measured five times, the least span kept: a busy machine stalling a task only adds to it
// (the leaves last 3 ms, so that a stall of a scheduler's time slice stays well under the gap
// between the right span and a wrong one).
TEST(WorkSpan, NestedLoopsAndInvokesCountAtEveryDepth) {
  using namespace mccd::detail;
  tbb::task_arena one(1);
  double least_span = 1e9;
  for (int run = 0; run < 5; ++run)
    one.execute([&] {
      WorkSpanRecorder recorder;
      const StageClock clock(&recorder);
      // 2 outer tasks, each a loop of 8 inner tasks of 3 ms: work 48 ms, span about 3 ms (the
      // outer task whole would be 24 ms).
      for_each_index(
          2, [](std::size_t) { for_each_index(8, [](std::size_t) { spin(3e-3); }, tbb::simple_partitioner()); },
          tbb::simple_partitioner());
      // A recursive invoke 3 levels deep, 3 ms at each leaf: work 24 ms, span about 3 ms.
      auto split = [](auto&& self, int depth) -> void {
        if (depth == 0) return spin(3e-3);
        invoke_pair([&] { self(self, depth - 1); }, [&] { self(self, depth - 1); });
      };
      split(split, 3);
      const WorkSpan ws = clock.work_span(clock.seconds());
      EXPECT_GE(ws.work, 72e-3);
      EXPECT_GE(ws.span, 6e-3);  // at least one leaf of each
      least_span = std::min(least_span, ws.span);
    });
  // About 6 ms; counting a nested loop or invoke as one task gives at least 36 ms (24 + 12).
  EXPECT_LE(least_span, 20e-3) << "a nested loop counted as one task";
}
