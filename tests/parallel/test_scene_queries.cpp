// The simulator queries agree with a full step at every step of every generated scene, for
// every method, and leave the scene as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <mccd/parallel/scene.h>

#include "fixtures/scenes.h"

using namespace mccd;

namespace {

std::vector<PositionsView> views(const std::vector<Positions>& frame) { return {frame.begin(), frame.end()}; }

bool same_pair(const Contact& a, const Contact& b) {
  return a.kind == b.kind && a.mesh_a == b.mesh_a && a.a == b.a && a.mesh_b == b.mesh_b && a.b == b.b;
}

void expect_queries_agree(const AnimatedScene& s, Method method) {
  SceneOptions o;
  o.method = method;
  Scene full(s.meshes, o), queried(s.meshes, o);
  std::size_t steps_with_contacts = 0;
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const auto a = views(s.frames[f - 1]), b = views(s.frames[f]);
    const StepResult r = full.step(a, b);
    StepStats qs;
    EXPECT_EQ(queried.is_collision_free(a, b, &qs), r.contacts.empty()) << s.name << " step " << f;
    EXPECT_LE(qs.vf_tests + qs.ee_tests, r.stats.vf_tests + r.stats.ee_tests);
    const double t = queried.earliest_impact(a, b, &qs);
    EXPECT_EQ(t, r.earliest_toi) << s.name << " step " << f;
    EXPECT_LE(qs.vf_tests + qs.ee_tests, r.stats.vf_tests + r.stats.ee_tests);
    const std::vector<Contact> cand = queried.candidates(a, b, &qs);
    // every elementary test of the full step is one candidate, and every contact is among them
    EXPECT_EQ(cand.size(), r.stats.vf_tests + r.stats.ee_tests) << s.name << " step " << f;
    EXPECT_TRUE(std::is_sorted(cand.begin(), cand.end()));
    std::size_t i = 0;
    for (const Contact& c : r.contacts) {
      while (i < cand.size() && cand[i] < c) ++i;
      ASSERT_LT(i, cand.size());
      ASSERT_TRUE(same_pair(cand[i], c));
      EXPECT_LE(cand[i].toi, c.toi);  // a lower bound of the contact time
    }
    // the queries changed nothing: the next full step of `queried` equals `full`'s
    const StepResult rq = queried.step(a, b);
    ASSERT_EQ(rq.contacts, r.contacts);
    steps_with_contacts += !r.contacts.empty();
  }
  EXPECT_GT(steps_with_contacts, 0u) << s.name;
}

}  // namespace

TEST(SceneQueries, FoldingCloth) {
  for (Method m : {Method::Traverse, Method::Phc, Method::Fbd}) expect_queries_agree(make_folding_cloth(30, 21), m);
}
TEST(SceneQueries, DeformingSpheres) {
  for (Method m : {Method::BruteForce, Method::Fbd}) expect_queries_agree(make_deforming_spheres(3, 8, 21), m);
}
TEST(SceneQueries, RandomTriangles) { expect_queries_agree(make_random_triangles(1500, 16, 5), Method::Fbd); }
TEST(SceneQueries, TwistingTube) { expect_queries_agree(make_twisting_tube(40, 16, 21), Method::Fbd); }

TEST(SceneQueries, AdvanceIsUnaffectedByQueries) {
  const AnimatedScene s = make_folding_cloth(25, 15);
  Scene a(s.meshes), b(s.meshes);
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const auto next = views(s.frames[f]);
    // queries on some unrelated step in between
    const auto x = views(s.frames[s.frames.size() - 1]), y = views(s.frames[0]);
    b.is_collision_free(x, y);
    b.earliest_impact(y, x);
    b.candidates(x, y);
    ASSERT_EQ(a.advance(next).contacts, b.advance(next).contacts) << "step " << f;
  }
}

TEST(SceneQueries, CollisionFreeStopsEarly) {
  // A cloth folding through itself: once contacts are plentiful, the first-contact query runs
  // far fewer elementary tests than the full step.
  const AnimatedScene s = make_folding_cloth(60, 11);
  Scene sc(s.meshes);
  const auto a = views(s.frames[9]), b = views(s.frames[10]);
  const StepResult r = sc.step(a, b);
  ASSERT_GT(r.contacts.size(), 100u);
  StepStats qs;
  EXPECT_FALSE(sc.is_collision_free(a, b, &qs));
  EXPECT_LT(qs.vf_tests + qs.ee_tests, (r.stats.vf_tests + r.stats.ee_tests) / 2);
}
