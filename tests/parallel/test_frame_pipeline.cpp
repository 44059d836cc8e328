// The frame pipeline (flow graph) gives the results of stepping frame after frame, in order,
// and stops cleanly on a bad frame.
#include <mccd/parallel/frame_pipeline.h>

#include <gtest/gtest.h>

#include <stdexcept>

#include <oneapi/tbb/task_arena.h>

#include "fixtures/scenes.h"
#include <mccd/geometry/error.h>

using namespace mccd;

namespace {
std::vector<PositionsView> views(const std::vector<Positions>& f) { return {f.begin(), f.end()}; }

FrameSource source_of(const AnimatedScene& s, std::size_t& next) {
  next = 1;
  return [&s, &next](std::vector<Positions>& out) {
    if (next >= s.frames.size()) return false;
    out = s.frames[next++];
    return true;
  };
}
}  // namespace

TEST(FramePipeline, SameResultsAsSteppingInOrder) {
  const AnimatedScene s = make_deforming_spheres(3, 8, 13);
  for (int substeps : {1, 3}) {
    // reference: explicit steps, sub-steps interpolated linearly
    std::vector<std::vector<Contact>> expected;
    {
      Scene ref(s.meshes);
      std::vector<Positions> prev = s.frames[0];
      for (std::size_t f = 1; f < s.frames.size(); ++f)
        for (int k = 1; k <= substeps; ++k) {
          const double u = double(k) / substeps;
          std::vector<Positions> end = s.frames[f];
          if (k < substeps)
            for (std::size_t m = 0; m < end.size(); ++m) end[m].mat() = (1 - u) * s.frames[f - 1][m].mat() + u * s.frames[f][m].mat();
          expected.push_back(ref.step(views(prev), views(end)).contacts);
          prev = end;
        }
    }
    // in the caller's arena, and in arenas of one thread (the stepper writes each sub-step
    // itself) and two (the writer node beside it)
    for (int threads : {0, 1, 2}) {
      Scene scene(s.meshes);
      std::size_t next = 0, seen = 0, total = 0, steps = 0;
      PipelineOptions po;
      po.substeps = substeps;
      po.frames_in_flight = 2;
      auto run = [&] {
        steps = run_frame_pipeline(
            scene, s.frames[0], source_of(s, next),
            [&](const PipelineStep& st) {
              ASSERT_EQ(st.index, seen + 1);  // in order
              ASSERT_LT(seen, expected.size());
              EXPECT_EQ(st.result.contacts, expected[seen]) << "step " << st.index << ", arena " << threads;
              total += st.result.contacts.size();
              ++seen;
            },
            po);
      };
      if (threads == 0) {
        run();
      } else {
        tbb::task_arena arena(threads);
        arena.execute(run);
      }
      EXPECT_EQ(steps, expected.size());
      EXPECT_EQ(seen, expected.size());
      EXPECT_GT(total, 0u);
    }
  }
}

TEST(FramePipeline, ErrorInTheSinkStopsAndIsRethrownOnOneThread) {
  const AnimatedScene s = make_deforming_spheres(2, 8, 9);
  for (int threads : {1, 2}) {
    Scene scene(s.meshes);
    std::size_t next = 0, seen = 0;
    PipelineOptions po;
    po.substeps = 2;
    tbb::task_arena arena(threads);
    EXPECT_THROW(arena.execute([&] {
      run_frame_pipeline(
          scene, s.frames[0], source_of(s, next),
          [&](const PipelineStep& st) {
            if (st.index == 4) throw Error("disk full");
            ++seen;
          },
          po);
    }),
                 Error);
    EXPECT_EQ(seen, 3u) << threads << " threads";
  }
}

TEST(FramePipeline, ErrorInAFrameStopsAndIsRethrown) {
  const AnimatedScene s = make_folding_cloth(10, 8);
  Scene scene(s.meshes);
  std::size_t next = 1, seen = 0;
  FrameSource source = [&](std::vector<Positions>& out) {
    if (next >= s.frames.size()) return false;
    if (next == 5) throw Error("frame5.ply: truncated binary data: vertex 3 of 121");
    out = s.frames[next++];
    return true;
  };
  try {
    run_frame_pipeline(scene, s.frames[0], source, [&](const PipelineStep&) { ++seen; });
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame5.ply"), std::string::npos);
  }
  EXPECT_LE(seen, 4u);  // only steps before the bad frame were written
}

TEST(FramePipeline, WrongFrameShapeIsRefusedByTheScene) {
  const AnimatedScene s = make_folding_cloth(10, 4);
  Scene scene(s.meshes);
  bool given = false;
  FrameSource source = [&](std::vector<Positions>& out) {
    if (given) return false;
    given = true;
    out = {Positions(s.frames[1][0].mat().topRows(5))};
    return true;
  };
  PipelineOptions po;
  po.substeps = 2;
  EXPECT_THROW(run_frame_pipeline(scene, s.frames[0], source, [](const PipelineStep&) {}, po), Error);
  po.substeps = 0;
  EXPECT_THROW(run_frame_pipeline(scene, s.frames[0], source, [](const PipelineStep&) {}, po), Error);
}
