// Scene: the methods (brute force, traversal from the root, front tracking) and both
// representative rules must give identical contacts at every step of generated scenes; bad
// input must leave no trace.
#include <mccd/parallel/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <oneapi/tbb/task_arena.h>

#include "fixtures/scenes.h"
#include <mccd/geometry/error.h>

using namespace mccd;

namespace {

std::vector<PositionsView> views(const std::vector<Positions>& frame) {
  return std::vector<PositionsView>(frame.begin(), frame.end());
}

std::string describe(const Contact& c) {
  return std::string(c.kind == ContactKind::VertexFace ? "VF " : "EE ") + std::to_string(c.mesh_a) + ":" +
         std::to_string(c.a) + " " + std::to_string(c.mesh_b) + ":" + std::to_string(c.b);
}

/// Runs every step of `s` with each method in its own scene and checks identical results;
/// the front also under the other representative rule. Returns the total number of contacts
/// seen.
std::size_t expect_methods_agree(const AnimatedScene& s, SceneOptions opt = {}) {
  SceneOptions other = opt;
  other.representatives =
      resolved_representatives(opt) == Representatives::Leaf ? Representatives::Canonical : Representatives::Leaf;
  Scene brute(s.meshes, opt), trav(s.meshes, opt), front(s.meshes, opt), rule(s.meshes, other);
  std::size_t total = 0;
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    auto next = views(s.frames[f]);
    StepResult rb = brute.advance(next, Method::BruteForce);
    StepResult rt = trav.advance(next, Method::Traverse);
    StepResult rf = front.advance(next, Method::Fbd);
    StepResult rr = rule.advance(next, Method::Fbd);
    EXPECT_EQ(rr.contacts, rf.contacts) << s.name << " step " << f << ": the representative rules differ";
    EXPECT_EQ(rb.contacts.size(), rt.contacts.size()) << s.name << " step " << f;
    EXPECT_EQ(rb.contacts.size(), rf.contacts.size()) << s.name << " step " << f;
    if (rb.contacts != rt.contacts || rb.contacts != rf.contacts) {
      ADD_FAILURE() << s.name << " step " << f << ": contacts differ";
      for (std::size_t i = 0; i < std::max({rb.contacts.size(), rt.contacts.size(), rf.contacts.size()}); ++i) {
        const std::string b = i < rb.contacts.size() ? describe(rb.contacts[i]) : "-";
        const std::string t = i < rt.contacts.size() ? describe(rt.contacts[i]) : "-";
        const std::string fr = i < rf.contacts.size() ? describe(rf.contacts[i]) : "-";
        if (b != t || b != fr) {
          ADD_FAILURE() << "first difference at " << i << ": brute " << b << ", traverse " << t << ", front " << fr;
          break;
        }
      }
      return total;
    }
    EXPECT_EQ(rb.earliest_toi, rf.earliest_toi);
    for (std::size_t i = 1; i < rf.contacts.size(); ++i) EXPECT_TRUE(rf.contacts[i - 1] < rf.contacts[i]);
    total += rf.contacts.size();
  }
  return total;
}

}  // namespace

TEST(SceneMethods, FoldingClothAgree) {
  AnimatedScene s = make_folding_cloth(40, 51);  // 3,200 triangles, 50 steps
  EXPECT_GT(expect_methods_agree(s), 100u);
}

TEST(SceneMethods, LargeFoldingClothAgree) {
  AnimatedScene s = make_folding_cloth(100, 51);  // 20,000 triangles, 50 steps
  EXPECT_GT(expect_methods_agree(s), 1000u);
}

TEST(SceneMethods, DeformingSpheresAgree) {
  AnimatedScene s = make_deforming_spheres(4, 10, 51);  // 4 x 360 triangles
  EXPECT_GT(s.num_triangles(), 1000u);
  EXPECT_GT(expect_methods_agree(s), 100u);
}

TEST(SceneMethods, RandomTrianglesAgree) {
  AnimatedScene s = make_random_triangles(3000, 51, 7);
  EXPECT_GT(expect_methods_agree(s), 10u);
}

TEST(SceneMethods, TwistingTubeAgree) {
  AnimatedScene s = make_twisting_tube(60, 30, 51);  // 3,540 triangles
  EXPECT_GT(expect_methods_agree(s), 10u);
}

TEST(SceneMethods, AabbAgrees) {
  SceneOptions opt;
  opt.volume = VolumeKind::Aabb;
  AnimatedScene s = make_folding_cloth(30, 31);
  EXPECT_GT(expect_methods_agree(s, opt), 10u);
}

TEST(SceneMethods, MinDistanceAgrees) {
  SceneOptions opt;
  opt.min_distance = 0.01;
  AnimatedScene s = make_deforming_spheres(3, 8, 21);
  EXPECT_GT(expect_methods_agree(s, opt), 10u);
}

TEST(SceneMethods, TreesLeafSizesAndRulesAgree) {
  // Every tree, leaf size and representative rule finds the same contacts as brute force.
  AnimatedScene cloth = make_folding_cloth(24, 16), spheres = make_deforming_spheres(3, 8, 16);
  for (const AnimatedScene* s : {&cloth, &spheres})
    for (BvhBuild b : {BvhBuild::Median, BvhBuild::Sah})
      for (unsigned leaf : {1u, 2u, 3u, 4u, 8u, 16u, 21u}) {
        SceneOptions opt;
        opt.bvh = b;
        opt.leaf_size = leaf;
        SCOPED_TRACE(s->name + std::string(" ") + to_string(b) + " leaf " + std::to_string(leaf));
        EXPECT_GT(expect_methods_agree(*s, opt), 10u);
      }
}

TEST(SceneFront, RebuildPolicyDoesNotChangeContacts) {
  AnimatedScene s = make_folding_cloth(30, 41);
  SceneOptions always, never;
  always.rebuild_sprout_ratio = always.rebuild_invalid_ratio = 1e-9;  // rebuild every other step
  never.rebuild_sprout_ratio = never.rebuild_invalid_ratio = 1e9;     // track forever
  Scene a(s.meshes, always), n(s.meshes, never), t(s.meshes);
  std::uint64_t rebuilds_a = 0, rebuilds_n = 0;
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    auto next = views(s.frames[f]);
    StepResult ra = a.advance(next, Method::Fbd), rn = n.advance(next, Method::Fbd),
               rt = t.advance(next, Method::Traverse);
    ASSERT_EQ(ra.contacts, rt.contacts) << "step " << f;
    ASSERT_EQ(rn.contacts, rt.contacts) << "step " << f;
    rebuilds_a += ra.stats.rebuilds;
    rebuilds_n += rn.stats.rebuilds;
    if (f > 1) {
      EXPECT_GT(rn.stats.front_size, 0u);
    }
  }
  EXPECT_EQ(rebuilds_n, 1u);  // only the first build
  EXPECT_GT(rebuilds_a, 5u);  // whenever anything sprouted
}

TEST(SceneFront, FrontTestsFewerVolumesThanTraverse) {
  AnimatedScene s = make_folding_cloth(60, 41);
  Scene f(s.meshes), t(s.meshes);
  std::uint64_t vf = 0, vt = 0;
  for (std::size_t i = 1; i < s.frames.size(); ++i) {
    auto next = views(s.frames[i]);
    vf += f.advance(next, Method::Fbd).stats.volume_tests;
    vt += t.advance(next, Method::Traverse).stats.volume_tests;
  }
  EXPECT_LT(vf, vt);
}

TEST(SceneInput, RefusedStepLeavesSceneUnchanged) {
  AnimatedScene s = make_folding_cloth(20, 6);
  Scene a(s.meshes), b(s.meshes);
  a.advance(views(s.frames[1]));
  b.advance(views(s.frames[1]));
  Positions bad = s.frames[2][0];
  bad(17, 1) = std::numeric_limits<double>::quiet_NaN();
  try {
    a.advance(std::vector<PositionsView>{bad});
    FAIL() << "NaN accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 17"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mesh 0"), std::string::npos) << e.what();
  }
  Positions short_frame(s.frames[2][0].mat().topRows(10));
  EXPECT_THROW(a.advance(std::vector<PositionsView>{short_frame}), Error);
  EXPECT_THROW(a.advance(std::vector<PositionsView>{}), Error);
  EXPECT_THROW(a.step(std::vector<PositionsView>{s.frames[1][0]}, std::vector<PositionsView>{bad}), Error);
  for (int f = 2; f < 6; ++f) {
    StepResult ra = a.advance(views(s.frames[f])), rb = b.advance(views(s.frames[f]));
    EXPECT_EQ(ra.contacts, rb.contacts);
    EXPECT_EQ(ra.stats.volume_tests, rb.stats.volume_tests);
  }
}

TEST(SceneInput, RefusesBadMeshesAndOptions) {
  TriMesh m = make_grid_mesh(2);
  m.faces[3][1] = 99;
  EXPECT_THROW(Scene({m}), Error);
  SceneOptions opt;
  opt.min_distance = -1;
  EXPECT_THROW(Scene({make_grid_mesh(2)}, opt), Error);
}

TEST(SceneContacts, MultiMeshIdsAreLocal) {
  AnimatedScene s = make_deforming_spheres(3, 6, 11);
  Scene sc(s.meshes);
  bool saw_inter = false;
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    StepResult r = sc.advance(views(s.frames[f]));
    for (const Contact& c : r.contacts) {
      ASSERT_LT(c.mesh_a, 3u);
      ASSERT_LT(c.mesh_b, 3u);
      if (c.kind == ContactKind::VertexFace) {
        EXPECT_LT(c.a, s.meshes[c.mesh_a].num_vertices());
        EXPECT_LT(c.b, s.meshes[c.mesh_b].num_faces());
      } else {
        const MeshTopology ta(s.meshes[c.mesh_a].num_vertices(), s.meshes[c.mesh_a].faces);
        EXPECT_EQ(ta.edges()[c.a][0], c.a_vertices[0]);
        EXPECT_EQ(ta.edges()[c.a][1], c.a_vertices[1]);
      }
      saw_inter |= c.mesh_a != c.mesh_b;
      EXPECT_GE(c.toi, 0.0);
      EXPECT_LE(c.toi, 1.0);
    }
  }
  EXPECT_TRUE(saw_inter);
}

TEST(SceneContacts, PointThroughTriangleKnownAnswer) {
  // mesh 0: one triangle in z = 0; mesh 1: a small triangle whose corner 0 drops through it
  TriMesh floor, drop;
  floor.vertices = {Vec3(-1, -1, 0), Vec3(2, -1, 0), Vec3(-1, 2, 0)};
  floor.faces = {{0, 1, 2}};
  drop.vertices = {Vec3(0, 0, 0.5), Vec3(0.1, 0, 0.9), Vec3(0, 0.1, 0.9)};
  drop.faces = {{0, 1, 2}};
  Scene sc({floor, drop});
  Positions f1 = floor.vertices, d1 = drop.vertices;
  d1.mat().col(2).array() -= 0.8;  // corner 0: z 0.5 -> -0.3, hits at t = 0.625; the others stay above
  for (Method m : {Method::BruteForce, Method::Traverse, Method::Phc, Method::Fbd}) {
    StepResult r = sc.step(std::vector<PositionsView>{floor.vertices, drop.vertices},
                           std::vector<PositionsView>{f1, d1}, m);
    ASSERT_EQ(r.contacts.size(), 1u) << to_string(m);
    const Contact& c = r.contacts[0];
    EXPECT_EQ(c.kind, ContactKind::VertexFace);
    EXPECT_EQ(c.mesh_a, 1u);
    EXPECT_EQ(c.a, 0u);
    EXPECT_EQ(c.mesh_b, 0u);
    EXPECT_EQ(c.b, 0u);
    EXPECT_LE(c.toi, 0.625);
    EXPECT_GT(c.toi, 0.625 - 1e-6);
    EXPECT_EQ(r.earliest_toi, c.toi);
  }
  // moving the other way only half as far: no contact
  Positions d2 = drop.vertices;
  d2.mat().col(2).array() -= 0.4;
  StepResult r = sc.step(std::vector<PositionsView>{floor.vertices, drop.vertices},
                         std::vector<PositionsView>{f1, d2});
  EXPECT_TRUE(r.contacts.empty());
  EXPECT_TRUE(std::isinf(r.earliest_toi));
}

TEST(SceneContacts, AdvanceEqualsExplicitSteps) {
  AnimatedScene s = make_twisting_tube(30, 12, 41);
  Scene a(s.meshes), b(s.meshes);
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    StepResult ra = a.advance(views(s.frames[f]));
    StepResult rb = b.step(views(s.frames[f - 1]), views(s.frames[f]));
    ASSERT_EQ(ra.contacts, rb.contacts) << "step " << f;
  }
}

TEST(SceneContacts, OrphanPairsAreFoundBetweenAdjacentTriangles) {
  // A fan of two triangles sharing vertex 0 only; the far corner of one swings through the
  // other. Under the canonical rule every carrier pair is adjacent, so only the orphan set can
  // find the contact; under the leaf rule, the leaf pair (or the one leaf) of the two.
  TriMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.3, 0.3, 0.5), Vec3(0.4, 0.2, 0.5)};
  m.faces = {{0, 1, 2}, {0, 3, 4}};
  for (Representatives rule : {Representatives::Canonical, Representatives::Leaf})
    for (unsigned leaf : {1u, 2u}) {
      SceneOptions opt;
      opt.representatives = rule;
      opt.leaf_size = leaf;
      Scene sc({m}, opt);
      if (rule == Representatives::Canonical)
        EXPECT_GT(sc.orphan_vf_count(), 0u);
      else
        EXPECT_EQ(sc.orphan_vf_count(), 0u);
      Positions end = m.vertices;
      end(3, 2) = -0.5;  // vertex 3 passes through face 0 at t = 0.5
      for (Method meth : {Method::BruteForce, Method::Traverse, Method::Phc, Method::Fbd}) {
        StepResult r = sc.step(m.vertices, end, meth);
        bool found = false;
        for (const Contact& c : r.contacts) found |= c.kind == ContactKind::VertexFace && c.a == 3 && c.b == 0;
        EXPECT_TRUE(found) << to_string(meth) << " " << to_string(rule) << " leaf " << leaf;
        if (meth != Method::BruteForce && rule == Representatives::Canonical) {
          EXPECT_GE(r.stats.orphan_vf_tested, 1u);
        }
      }
    }
}

TEST(SceneThreads, ResultsDoNotDependOnThreadCount) {
  AnimatedScene s = make_folding_cloth(50, 31);
  tbb::task_arena one(1), two(2), four(4);
  SceneOptions o1, o2, o4;
  o1.arena = &one;
  o2.arena = &two;
  o4.arena = &four;
  Scene a(s.meshes, o1), b(s.meshes, o2), c(s.meshes, o4);
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    auto next = views(s.frames[f]);
    StepResult ra = a.advance(next), rb = b.advance(next), rc = c.advance(next);
    ASSERT_EQ(ra.contacts, rb.contacts) << "step " << f;
    ASSERT_EQ(ra.contacts, rc.contacts) << "step " << f;
    EXPECT_EQ(ra.stats.volume_tests, rb.stats.volume_tests);
    EXPECT_EQ(ra.stats.front_size, rc.stats.front_size);
    EXPECT_EQ(ra.stats.sprouted, rc.stats.sprouted);
    EXPECT_EQ(ra.stats.rebuilds, rc.stats.rebuilds);
  }
}

TEST(SceneInput, EmptyAndTinyScenes) {
  Scene empty(std::vector<TriMesh>{});
  StepResult r = empty.step(std::vector<PositionsView>{}, std::vector<PositionsView>{});
  EXPECT_TRUE(r.contacts.empty());
  // one triangle, plus a vertex used by no triangle (it takes part in nothing)
  TriMesh one;
  one.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.2, 1)};
  one.faces = {{0, 1, 2}};
  Scene s({one});
  Positions end = one.vertices;
  end(3, 2) = -1;  // the loose vertex passes through the triangle: not a contact
  for (Method m : {Method::BruteForce, Method::Traverse, Method::Phc, Method::Fbd}) {
    StepResult q = s.step(one.vertices, end, m);
    EXPECT_TRUE(q.contacts.empty()) << to_string(m);
  }
  EXPECT_EQ(s.orphan_vf_count(), 0u);
}
