// Embedding in a host that already runs oneTBB: a step runs in the caller's arena (or the one
// it is given), never limits the process's parallelism, and works nested inside the host's
// parallel_for and flow graph, with several scenes stepped concurrently. Stepping one scene
// from two threads at once is refused with an error instead of corrupting the scene.
#include <gtest/gtest.h>

#include <oneapi/tbb/flow_graph.h>
#include <oneapi/tbb/global_control.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include <atomic>
#include <thread>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/error.h>

#include "fixtures/scenes.h"

using namespace mccd;

namespace {

std::vector<PositionsView> views(const std::vector<Positions>& frame) { return {frame.begin(), frame.end()}; }

/// Contacts of every step of `s`, stepped serially on the calling thread in a 1-thread arena.
std::vector<std::vector<Contact>> reference(const AnimatedScene& s) {
  tbb::task_arena one(1);
  SceneOptions o;
  o.arena = &one;
  Scene sc(s.meshes, o);
  std::vector<std::vector<Contact>> out;
  for (std::size_t f = 1; f < s.frames.size(); ++f) out.push_back(sc.advance(views(s.frames[f])).contacts);
  return out;
}

}  // namespace

TEST(Embedding, RunsInTheGivenArenaWithoutChangingTheProcessLimit) {
  const AnimatedScene s = make_folding_cloth(30, 6);
  const auto before = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  tbb::task_arena two(2);
  SceneOptions o;
  o.arena = &two;
  Scene sc(s.meshes, o);
  std::atomic<int> max_index{-1};
  for (std::size_t f = 1; f < s.frames.size(); ++f) sc.advance(views(s.frames[f]));
  // Work of a step inside a 1-thread arena only ever sees slot 0 of that arena.
  tbb::task_arena one(1);
  one.execute([&] {
    SceneOptions caller;  // no arena: the caller's (this one)
    Scene in_caller(s.meshes, caller);
    in_caller.advance(views(s.frames[1]));
    max_index = tbb::this_task_arena::max_concurrency();
  });
  EXPECT_EQ(max_index.load(), 1);
  EXPECT_EQ(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism), before);
}

TEST(Embedding, StepsInsideTheHostsParallelFor) {
  // Eight independent scenes stepped from the host's parallel_for: each step's own parallel
  // stages (and its flow graph: above 8,192 triangles) nest inside the host's tasks.
  const AnimatedScene s = make_deforming_spheres(3, 30, 4);
  ASSERT_GE(s.num_triangles(), 8192u);
  const auto expected = reference(s);
  std::vector<std::unique_ptr<Scene>> scenes;
  for (int i = 0; i < 8; ++i) scenes.push_back(std::make_unique<Scene>(s.meshes));
  std::vector<std::vector<std::vector<Contact>>> got(scenes.size());
  tbb::parallel_for(std::size_t(0), scenes.size(), [&](std::size_t i) {
    for (std::size_t f = 1; f < s.frames.size(); ++f) got[i].push_back(scenes[i]->advance(views(s.frames[f])).contacts);
  });
  for (const auto& g : got) EXPECT_EQ(g, expected);
}

TEST(Embedding, StepsInsideAFlowGraphNode) {
  const AnimatedScene s = make_folding_cloth(70, 6);  // the step's own graph inside the host's
  ASSERT_GE(s.num_triangles(), 8192u);
  const auto expected = reference(s);
  Scene sc(s.meshes);
  std::vector<std::vector<Contact>> got;
  tbb::flow::graph g;
  std::size_t next = 1;
  tbb::flow::function_node<int, int> stepper(g, tbb::flow::serial, [&](int) {
    got.push_back(sc.advance(views(s.frames[next++])).contacts);
    return 0;
  });
  for (std::size_t f = 1; f < s.frames.size(); ++f) stepper.try_put(0);
  g.wait_for_all();
  EXPECT_EQ(got, expected);
}

TEST(Embedding, TwoScenesSteppedConcurrentlyFromTwoThreads) {
  const AnimatedScene s = make_twisting_tube(100, 45, 5);  // two step graphs at once
  ASSERT_GE(s.num_triangles(), 8192u);
  const auto expected = reference(s);
  Scene a(s.meshes), b(s.meshes);
  std::vector<std::vector<Contact>> ga, gb;
  std::thread ta([&] {
    for (std::size_t f = 1; f < s.frames.size(); ++f) ga.push_back(a.advance(views(s.frames[f])).contacts);
  });
  std::thread tb([&] {
    for (std::size_t f = 1; f < s.frames.size(); ++f) gb.push_back(b.advance(views(s.frames[f])).contacts);
  });
  ta.join();
  tb.join();
  EXPECT_EQ(ga, expected);
  EXPECT_EQ(gb, expected);
}

TEST(Embedding, ConcurrentStepOfOneSceneIsRefused) {
  // Two threads keep stepping one scene; whenever they overlap, one of them must get an
  // mccd::Error, and every step that ran must be right (the scene is never corrupted).
  const AnimatedScene s = make_folding_cloth(40, 3);
  SceneOptions traverse;
  traverse.method = Method::Traverse;
  Scene sc(s.meshes, traverse);
  Scene ref(s.meshes, traverse);
  const auto start = views(s.frames[0]), end = views(s.frames[1]);
  const std::vector<Contact> expected = ref.step(start, end).contacts;
  std::atomic<int> refused{0}, wrong{0}, done{0};
  auto worker = [&] {
    for (int i = 0; i < 200 && refused == 0; ++i) {
      try {
        if (sc.step(start, end).contacts != expected) ++wrong;
        ++done;
      } catch (const Error& e) {
        if (std::string(e.what()).find("already running") != std::string::npos) ++refused;
      }
    }
  };
  std::thread t1(worker), t2(worker);
  t1.join();
  t2.join();
  EXPECT_GT(refused.load(), 0) << "the threads never overlapped in 400 steps";
  EXPECT_EQ(wrong.load(), 0);
  EXPECT_GT(done.load(), 0);
  // and the scene still works
  EXPECT_EQ(sc.step(start, end).contacts, expected);
}

TEST(Embedding, IsolatedStepInsideTaskGroupOfTheHost) {
  // The host waits on its own task_group while steps run in its tasks: no deadlock, right
  // results (the step isolates its own waits from the host's outer tasks).
  const AnimatedScene s = make_deforming_spheres(2, 40, 4);
  ASSERT_GE(s.num_triangles(), 8192u);
  const auto expected = reference(s);
  std::vector<std::unique_ptr<Scene>> scenes;
  for (int i = 0; i < 4; ++i) scenes.push_back(std::make_unique<Scene>(s.meshes));
  std::vector<std::vector<std::vector<Contact>>> got(scenes.size());
  tbb::task_group tg;
  for (std::size_t i = 0; i < scenes.size(); ++i)
    tg.run([&, i] {
      for (std::size_t f = 1; f < s.frames.size(); ++f) got[i].push_back(scenes[i]->advance(views(s.frames[f])).contacts);
    });
  tg.wait();
  for (const auto& g : got) EXPECT_EQ(g, expected);
}
