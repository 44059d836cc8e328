// Every method (bruteforce, traverse, phc, fbd) and both representative rules return identical
// contacts, and phc and fbd return identical contacts and counts at 1, 2, 3, 4 and 8 threads, on
// the generated scenes at every step and on the real cloth-ball step (whose contact regions
// run their narrow phase in parallel pieces: the same tests as the serial traversal's).
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <filesystem>
#include <memory>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/frame_sequence.h>

#include "fixtures/scenes.h"
#include "support/data.h"
#include "support/real_step.h"

using namespace mccd;

namespace {

std::vector<PositionsView> views(const std::vector<Positions>& frame) { return {frame.begin(), frame.end()}; }

constexpr int kThreadCounts[] = {1, 2, 3, 4, 8};

/// Runs `s` with traverse as the reference and every parallel method at every thread count in
/// its own arena; checks contacts (and the counts that must not depend on threads) each step.
void expect_all_agree(const AnimatedScene& s, bool with_brute_force) {
  SceneOptions canonical_rule;
  canonical_rule.representatives = Representatives::Canonical;
  Scene reference(s.meshes), brute(s.meshes), canonical(s.meshes, canonical_rule);
  struct Variant {
    Method method;
    int threads;
    std::unique_ptr<tbb::task_arena> arena;
    std::unique_ptr<Scene> scene;
  };
  std::vector<Variant> variants;
  for (Method m : {Method::Phc, Method::Fbd})
    for (int t : kThreadCounts) {
      Variant v{m, t, std::make_unique<tbb::task_arena>(t), nullptr};
      SceneOptions o;
      o.method = m;
      o.arena = v.arena.get();
      v.scene = std::make_unique<Scene>(s.meshes, o);
      variants.push_back(std::move(v));
    }
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const auto next = views(s.frames[f]);
    const StepResult ref = reference.advance(next, Method::Traverse);
    if (with_brute_force) {
      ASSERT_EQ(brute.advance(next, Method::BruteForce).contacts, ref.contacts) << s.name << " step " << f;
    }
    ASSERT_EQ(canonical.advance(next, Method::Fbd).contacts, ref.contacts) << s.name << " step " << f << " canonical";
    StepResult base[2];
    for (Variant& v : variants) {
      StepResult r = v.scene->advance(next);
      ASSERT_EQ(r.contacts, ref.contacts) << s.name << " step " << f << " " << to_string(v.method) << " " << v.threads
                                          << " threads";
      // the narrow phase's counts are those of the serial traversal (whose queues run whole:
      // a heavy unit's queues run in parallel pieces only under phc and fbd)
      EXPECT_EQ(r.stats.feature_box_tests, ref.stats.feature_box_tests) << to_string(v.method) << " " << v.threads;
      EXPECT_EQ(r.stats.vf_filtered, ref.stats.vf_filtered);
      EXPECT_EQ(r.stats.ee_filtered, ref.stats.ee_filtered);
      EXPECT_EQ(r.stats.vf_tests, ref.stats.vf_tests);
      EXPECT_EQ(r.stats.ee_tests, ref.stats.ee_tests);
      StepResult& b = base[v.method == Method::Fbd];
      if (v.threads == 1) {
        b = std::move(r);
        continue;
      }
      EXPECT_EQ(r.stats.volume_tests, b.stats.volume_tests) << v.threads << " threads";
      EXPECT_EQ(r.stats.vf_tests, b.stats.vf_tests);
      EXPECT_EQ(r.stats.ee_tests, b.stats.ee_tests);
      EXPECT_EQ(r.stats.front_size, b.stats.front_size);
      EXPECT_EQ(r.stats.sprouted, b.stats.sprouted);
      EXPECT_EQ(r.stats.rebuilds, b.stats.rebuilds);
    }
  }
}

}  // namespace

TEST(MethodsAndThreads, FoldingCloth) { expect_all_agree(make_folding_cloth(40, 31), true); }
TEST(MethodsAndThreads, DeformingSpheres) { expect_all_agree(make_deforming_spheres(4, 10, 31), true); }
TEST(MethodsAndThreads, RandomTriangles) { expect_all_agree(make_random_triangles(2000, 21, 3), true); }
TEST(MethodsAndThreads, TwistingTube) { expect_all_agree(make_twisting_tube(40, 20, 31), true); }

TEST(MethodsAndThreads, ClothBallRealStep) {
  const auto dir = test::cloth_ball_frames();
  MCCD_REQUIRE_DATA(dir);
  const AnimatedScene s = test::cloth_ball_step(dir);
  expect_all_agree(s, true);
}

TEST(MethodsAndThreads, FlowGraphEqualsStagesInSequence) {
  // 9,800 triangles: above the size under which a scene calls its stages in sequence anyway
  const AnimatedScene s = make_folding_cloth(70, 13);
  ASSERT_GE(s.num_triangles(), 8192u);
  SceneOptions seq;
  seq.flow_graph = false;
  for (Method m : {Method::Traverse, Method::Phc, Method::Fbd}) {
    seq.method = m;
    SceneOptions graph = seq;
    graph.flow_graph = true;
    Scene a(s.meshes, seq), b(s.meshes, graph);
    for (std::size_t f = 1; f < s.frames.size(); ++f) {
      const auto next = views(s.frames[f]);
      const StepResult ra = a.advance(next), rb = b.advance(next);
      ASSERT_EQ(ra.contacts, rb.contacts) << to_string(m) << " step " << f;
      EXPECT_EQ(ra.stats.volume_tests, rb.stats.volume_tests);
      EXPECT_EQ(ra.stats.feature_box_tests, rb.stats.feature_box_tests);
      EXPECT_EQ(ra.stats.vf_tests + ra.stats.ee_tests, rb.stats.vf_tests + rb.stats.ee_tests);
    }
  }
}
