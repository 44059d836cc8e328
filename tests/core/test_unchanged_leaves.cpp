// Leaves that repeat the previous step (core/unchanged_leaves.h): a scene that skips them
// reports, step by step, the contacts of a scene that has never seen the step before.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <mccd/core/unchanged_leaves.h>
#include <mccd/parallel/scene.h>

#include "fixtures/scenes.h"

using namespace mccd;

namespace {

std::vector<PositionsView> views(const std::vector<Positions>& frame) { return {frame.begin(), frame.end()}; }

/// The step from frame f - 1 to f by a scene built at frame f - 1 (no previous step).
StepResult fresh_step(const AnimatedScene& a, std::size_t f, Method method = Method::Fbd,
                      const SceneOptions& options = {}) {
  std::vector<TriMesh> meshes = a.meshes;
  for (std::size_t m = 0; m < meshes.size(); ++m) meshes[m].vertices = a.frames[f - 1][m];
  Scene s(meshes, options);
  return s.step(views(a.frames[f - 1]), views(a.frames[f]), method);
}

/// Two triangles of two meshes, a corner of the second lying inside the first: a contact at
/// t = 0 in every step while neither moves.
AnimatedScene resting_contact(std::size_t frames) {
  AnimatedScene a;
  TriMesh t1, t2;
  t1.vertices = Positions({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)});
  t1.faces = {{0, 1, 2}};
  t2.vertices = Positions({Vec3(0.25, 0.25, 0), Vec3(0.25, 0.25, 1), Vec3(1, 1, 1)});
  t2.faces = {{0, 1, 2}};
  a.meshes = {t1, t2};
  for (std::size_t f = 0; f < frames; ++f) a.frames.push_back({t1.vertices, t2.vertices});
  return a;
}

}  // namespace

TEST(UnchangedLeaves, TheRestingHalfIsSkippedWithTheSameContacts) {
  // The folding cloth's left half never moves; the right half folds over and through it.
  // Without self-collision culling (which certifies the flat half and skips its pairs before
  // they are looked at), the resting half's pairs are skipped as repeats; with it, the same
  // contacts.
  const AnimatedScene a = make_folding_cloth(16, 12);
  // leaves of 8 triangles: on this small cloth some leaf pairs then lie wholly in the resting
  // half at every step (with the default 16 some steps have none)
  SceneOptions with_culling;
  with_culling.leaf_size = 8;
  Scene culled(a.meshes, with_culling);
  SceneOptions o;
  o.leaf_size = 8;
  o.self_culling = false;
  Scene s(a.meshes, o);
  std::uint64_t repeated = 0, contacts = 0;
  for (std::size_t f = 1; f < a.frames.size(); ++f) {
    const StepResult r = s.advance(views(a.frames[f]));
    const StepResult fresh = fresh_step(a, f);
    ASSERT_EQ(r.contacts, fresh.contacts) << "step " << f;
    EXPECT_EQ(r.earliest_toi, fresh.earliest_toi) << "step " << f;
    EXPECT_EQ(fresh.stats.repeated_leaf_pairs, 0u);
    const StepResult c = culled.advance(views(a.frames[f]));
    ASSERT_EQ(c.contacts, fresh.contacts) << "step " << f;
    EXPECT_EQ(c.earliest_toi, fresh.earliest_toi) << "step " << f;
    // the first step notes which vertices move, so the second is the first to skip
    if (f >= 2) {
      EXPECT_GT(r.stats.repeated_leaf_pairs, 0u) << "step " << f;
    } else {
      EXPECT_EQ(r.stats.repeated_leaf_pairs, 0u) << "step " << f;
    }
    repeated += r.stats.repeated_leaf_pairs;
    contacts += r.contacts.size();
  }
  EXPECT_GT(contacts, 0u);
  EXPECT_GT(repeated, 0u);
}

TEST(UnchangedLeaves, APairThatFoundAContactIsTestedAgain) {
  // Nothing moves, and the same contact is there in every step: its leaves are never skipped.
  const AnimatedScene a = resting_contact(8);
  Scene s(a.meshes);
  const StepResult first = s.advance(views(a.frames[1]));
  ASSERT_EQ(first.contacts.size(), 1u);
  EXPECT_EQ(first.contacts[0].kind, ContactKind::VertexFace);
  EXPECT_EQ(first.earliest_toi, 0.0);
  for (std::size_t f = 2; f < a.frames.size(); ++f) {
    const StepResult r = s.advance(views(a.frames[f]));
    EXPECT_EQ(r.contacts, first.contacts) << "step " << f;
  }
}

TEST(UnchangedLeaves, QueriesAndBruteForceStepsInBetweenAreNotTrusted) {
  // A query's positions are not the scene's, and brute force does not process leaf pairs:
  // the step after either skips nothing, and every step reports what a fresh scene does.
  const AnimatedScene a = make_folding_cloth(16, 12);
  Scene s(a.meshes);
  for (std::size_t f = 1; f < a.frames.size(); ++f) {
    const bool after_query = f % 4 == 0, brute = f % 5 == 0, after_brute = f % 5 == 1 && f > 1;
    if (after_query) {
      // a query on other positions: the previous step's end moved by a little
      std::vector<Positions> moved = a.frames[f];
      for (Positions& p : moved)
        for (std::size_t v = 0; v < p.rows(); ++v) p(v, 2) += 0.001;
      (void)s.earliest_impact(views(a.frames[f - 1]), views(moved));
      (void)s.is_collision_free(views(a.frames[f - 1]), views(moved));
    }
    const Method m = brute ? Method::BruteForce : Method::Fbd;
    const StepResult r = s.advance(views(a.frames[f]), m);
    const StepResult fresh = fresh_step(a, f, m);
    ASSERT_EQ(r.contacts, fresh.contacts) << "step " << f;
    if (after_query || brute || after_brute) {
      EXPECT_EQ(r.stats.repeated_leaf_pairs, 0u) << "step " << f;
    }
  }
}

TEST(UnchangedLeaves, EveryMethodAfterRestingStepsAgrees) {
  // Steps skipped by one method leave nothing another method would see differently.
  const AnimatedScene a = make_folding_cloth(12, 10);
  for (Method m : {Method::Traverse, Method::Phc, Method::Fbd}) {
    Scene s(a.meshes);
    for (std::size_t f = 1; f < a.frames.size(); ++f) {
      const Method mf = f % 2 ? m : Method::Fbd;
      const StepResult r = s.advance(views(a.frames[f]), mf);
      ASSERT_EQ(r.contacts, fresh_step(a, f, Method::BruteForce).contacts) << to_string(m) << " step " << f;
    }
  }
}

TEST(UnchangedLeaves, AClothAtRestOnAStaticBallSkipsItsPairsWithTheBall) {
  // A cloth lying across a static ball (given the same positions every frame) and a second
  // cloth that keeps folding: from the second step on, the resting cloth's pairs, with itself
  // and with the static ball's leaves, are all skipped; the contacts are a fresh scene's.
  const AnimatedScene folding = make_folding_cloth(10, 8);
  TriMesh rest = make_grid_mesh(12, 1.0);
  // tilted 0.005 above the sphere (the coarse ball lies inside it): eight leaf pairs of the two
  // overlap, the triangles never meet
  for (std::size_t v = 0; v < rest.vertices.rows(); ++v) rest.vertices(v, 2) = 2.947 + 0.3 * rest.vertices(v, 0);
  const TriMesh ball = make_sphere_mesh(6, 8, 0.5, Vec3(0.0, 0.0, 2.42));
  AnimatedScene a;
  a.meshes = {folding.meshes[0], rest, ball};
  for (const std::vector<Positions>& f : folding.frames) a.frames.push_back({f[0], rest.vertices, ball.vertices});
  SceneOptions o;
  o.meshes = {MeshOptions{}, MeshOptions{}, MeshOptions{true, false}};
  Scene s(a.meshes, o);
  SceneOptions ro;
  ro.meshes = {MeshOptions{}, MeshOptions{true, false}};
  Scene r2({rest, ball}, ro);
  std::uint64_t contacts = 0;
  for (std::size_t f = 1; f < a.frames.size(); ++f) {
    const StepResult r = s.advance(views(a.frames[f]));
    ASSERT_EQ(r.contacts, fresh_step(a, f, Method::Fbd, o).contacts) << "step " << f;
    // the resting cloth and the ball alone: nothing is left to test from the second step on
    const StepResult q = r2.advance(std::vector<PositionsView>{rest.vertices, ball.vertices});
    EXPECT_TRUE(q.contacts.empty());
    if (f >= 2) {
      EXPECT_EQ(q.stats.leaf_pairs, 0u) << "step " << f;
      EXPECT_GT(q.stats.repeated_leaf_pairs, 0u) << "step " << f;
    }
    contacts += r.contacts.size();
  }
  EXPECT_GT(contacts, 0u);
}

TEST(UnchangedLeaves, ABallAtRestKeepsItsCertificateUntilItDentsItself) {
  // A ball given as deforming rests for some steps beside a cloth that keeps folding (its
  // certificate is kept from step to step), then its top cap is pushed down through its
  // bottom: that step it collides with itself, its certificate is computed again and fails,
  // and every step reports a fresh scene's contacts (which brute force confirms).
  const AnimatedScene folding = make_folding_cloth(10, 8);
  const TriMesh ball = make_sphere_mesh(8, 16, 0.5, Vec3(0.0, 0.0, 3.0));
  Positions dent(ball.vertices.rows());
  for (std::size_t v = 0; v < dent.rows(); ++v) {
    const Vec3 p = ball.vertices.point(v);
    dent.set_point(v, p.z() > 3.3 ? Vec3(p.x(), p.y(), p.z() - 0.95) : p);
  }
  AnimatedScene a;
  a.meshes = {folding.meshes[0], ball};
  const std::size_t dent_at = folding.frames.size() - 2;
  for (std::size_t f = 0; f < folding.frames.size(); ++f)
    a.frames.push_back({folding.frames[f][0], f < dent_at ? ball.vertices : dent});
  Scene s(a.meshes);
  for (std::size_t f = 1; f < a.frames.size(); ++f) {
    const StepResult r = s.advance(views(a.frames[f]));
    ASSERT_EQ(r.contacts, fresh_step(a, f).contacts) << "step " << f;
    ASSERT_EQ(r.contacts, fresh_step(a, f, Method::BruteForce).contacts) << "step " << f;
    const bool ball_contacts = std::any_of(r.contacts.begin(), r.contacts.end(), [&](const Contact& c) {
      return c.mesh_a == 1 && c.mesh_b == 1;
    });
    if (f <= dent_at) {
      EXPECT_EQ(ball_contacts, f == dent_at) << "step " << f;
    }
  }
}

TEST(UnchangedLeaves, AStepFromTheLastEndSkipsLikeAdvance) {
  // Scene::step with the last step's end as its start continues it (the frame pipeline's
  // way): it skips what advance() skips. A start one bit off the last end skips nothing, nor
  // does the step after it (every vertex moved in the nudged step). Every step reports a fresh
  // scene's contacts for its own start and end.
  const AnimatedScene a = make_folding_cloth(16, 12);
  SceneOptions o;
  o.leaf_size = 8;
  o.self_culling = false;
  Scene by_advance(a.meshes, o), by_step(a.meshes, o);
  for (std::size_t f = 1; f < a.frames.size(); ++f) {
    const StepResult r = by_advance.advance(views(a.frames[f]));
    ASSERT_EQ(r.contacts, fresh_step(a, f, Method::Fbd, o).contacts) << "step " << f;
    std::vector<Positions> start = a.frames[f - 1];
    if (f == 6)
      for (std::size_t v = 0; v < start[0].rows(); ++v) start[0](v, 0) = std::nextafter(start[0](v, 0), 1e9);
    const StepResult q = by_step.step(views(start), views(a.frames[f]));
    std::vector<TriMesh> at_start = a.meshes;
    for (std::size_t m = 0; m < at_start.size(); ++m) at_start[m].vertices = start[m];
    Scene fresh(at_start, o);
    ASSERT_EQ(q.contacts, fresh.step(views(start), views(a.frames[f])).contacts) << "step " << f;
    if (f == 6) {
      EXPECT_GT(r.stats.repeated_leaf_pairs, 0u);
      EXPECT_EQ(q.stats.repeated_leaf_pairs, 0u) << "not the last end: nothing is skipped";
    } else if (f == 7) {
      EXPECT_EQ(q.stats.repeated_leaf_pairs, 0u) << "every vertex moved in the step before";
    } else {
      EXPECT_EQ(q.stats.repeated_leaf_pairs, r.stats.repeated_leaf_pairs) << "step " << f;
      EXPECT_EQ(q.stats.leaf_pairs, r.stats.leaf_pairs) << "step " << f;
    }
  }
}

TEST(UnchangedLeaves, AllMovingThenRestingGivesAFreshScenesContacts) {
  // The folding cloth moved as a whole for its first steps, then at rest: no vertex repeats
  // while it moves, every resting step from the second on skips its pairs, and every step
  // reports a fresh scene's contacts.
  const AnimatedScene folding = make_folding_cloth(16, 12);
  AnimatedScene a;
  a.meshes = folding.meshes;
  for (std::size_t f = 0; f < 16; ++f) {
    std::vector<Positions> frame = folding.frames[std::min<std::size_t>(f, 10)];
    const double shift = 0.002 * double(std::min<std::size_t>(f, 10));
    for (Positions& p : frame)
      for (std::size_t v = 0; v < p.rows(); ++v) p(v, 1) += shift;
    a.frames.push_back(frame);
  }
  SceneOptions o;
  o.leaf_size = 8;
  o.self_culling = false;
  Scene s(a.meshes, o);
  for (std::size_t f = 1; f < a.frames.size(); ++f) {
    const StepResult r = s.advance(views(a.frames[f]));
    ASSERT_EQ(r.contacts, fresh_step(a, f, Method::Fbd, o).contacts) << "step " << f;
    // steps 1 to 10 move every vertex; 11 is the first at rest, 12 the first to repeat the
    // step before it
    if (f <= 11) {
      EXPECT_EQ(r.stats.repeated_leaf_pairs, 0u) << "step " << f;
    } else {
      EXPECT_GT(r.stats.repeated_leaf_pairs, 0u) << "step " << f;
    }
  }
}
