// Work and span of a step's stages (SceneOptions::work_span, parallel/tbb_executor.h): the
// same contacts as without; at one thread each stage's work is its own time and its span at
// most its work; through the flow graph the search and the self stage count as one branch
// whose span is the longer of theirs; off, nothing is measured.
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <algorithm>

#include <mccd/parallel/scene.h>

#include "fixtures/scenes.h"

using namespace mccd;

namespace {

std::vector<PositionsView> views(const std::vector<Positions>& frame) { return {frame.begin(), frame.end()}; }

void expect_consistent(const WorkSpan& ws, double stage_seconds, const char* what) {
  EXPECT_GE(ws.span, 0.0) << what;
  EXPECT_LE(ws.span, ws.work * (1 + 1e-9) + 1e-9) << what;
  // one thread: the stage's threads were busy exactly its wall time (clock reads aside)
  EXPECT_NEAR(ws.work, stage_seconds, 0.2 * stage_seconds + 2e-4) << what;
}

}  // namespace

TEST(WorkSpan, OneThreadWorkIsTheStageTimeAndContactsDoNotChange) {
  const AnimatedScene s = make_folding_cloth(40, 6);  // 3,200 triangles: the stages in sequence
  tbb::task_arena one(1);
  SceneOptions measured, plain;
  measured.work_span = true;
  measured.arena = plain.arena = &one;
  Scene a(s.meshes, measured), b(s.meshes, plain);
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
    // on one thread the prediction for one thread is the step's own time
    EXPECT_NEAR(st.predicted_seconds(1), st.t_total, 1e-9 + 1e-9 * st.t_total);
    EXPECT_LE(st.predicted_seconds(2), st.predicted_seconds(1) + 1e-12);
  }
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
  }
}
