// Static meshes and meshes without self-collision: the same contacts as the scene without the
// flags, less what the flags exclude; no update or refit for what never moves; misuse refused.
#include <gtest/gtest.h>

#include <cmath>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/error.h>

#include "fixtures/scenes.h"

using namespace mccd;

namespace {

/// A cloth folding through itself and through a sphere that does not move.
struct ClothAndBall {
  AnimatedScene cloth = make_folding_cloth(30, 21);
  TriMesh ball = make_sphere_mesh(8, 12, 0.2, Vec3(0.25, 0.0, 0.1));
  std::vector<TriMesh> meshes() const { return {cloth.meshes[0], ball}; }
};

std::vector<Contact> without_mesh_self(const std::vector<Contact>& all, std::uint32_t mesh) {
  std::vector<Contact> out;
  for (const Contact& c : all)
    if (!(c.mesh_a == mesh && c.mesh_b == mesh)) out.push_back(c);
  return out;
}

}  // namespace

TEST(StaticMeshes, SameContactsAsUnchangedPositionsAndNoRefit) {
  const ClothAndBall s;
  SceneOptions stat;
  stat.meshes = {MeshOptions{}, MeshOptions{.is_static = true}};
  for (Method m : {Method::BruteForce, Method::Traverse, Method::Phc, Method::Fbd}) {
    stat.method = m;
    SceneOptions moving = stat;
    moving.meshes.clear();
    Scene a(s.meshes(), stat), b(s.meshes(), moving);
    std::size_t with_ball = 0;
    for (std::size_t f = 1; f < s.cloth.frames.size(); ++f) {
      const Positions& cloth = s.cloth.frames[f][0];
      const StepResult ra = a.advance(std::vector<PositionsView>{cloth, PositionsView()});
      const StepResult rb = b.advance(std::vector<PositionsView>{cloth, s.ball.vertices});
      ASSERT_EQ(ra.contacts, rb.contacts) << to_string(m) << " step " << f;
      for (const Contact& c : ra.contacts) with_ball += c.mesh_a == 1 || c.mesh_b == 1;
      EXPECT_EQ(ra.stats.updated_vertices, s.cloth.meshes[0].num_vertices());
      EXPECT_EQ(rb.stats.updated_vertices, s.cloth.meshes[0].num_vertices() + s.ball.num_vertices());
      EXPECT_LT(ra.stats.refit_nodes, rb.stats.refit_nodes);
    }
    EXPECT_GT(with_ball, 10u) << to_string(m);
  }
}

TEST(StaticMeshes, GivenUnchangedPositionsAcceptedChangedRefused) {
  const ClothAndBall s;
  SceneOptions o;
  o.meshes = {MeshOptions{}, MeshOptions{.is_static = true}};
  Scene sc(s.meshes(), o);
  const Positions& cloth = s.cloth.frames[1][0];
  EXPECT_NO_THROW(sc.advance(std::vector<PositionsView>{cloth, s.ball.vertices}));
  Positions moved = s.ball.vertices;
  moved(5, 2) += 1e-9;
  try {
    sc.advance(std::vector<PositionsView>{cloth, moved});
    FAIL() << "a moved static mesh was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("static"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("vertex 5"), std::string::npos) << e.what();
  }
  // a moving mesh needs its positions
  EXPECT_THROW(sc.advance(std::vector<PositionsView>{PositionsView(), PositionsView()}), Error);
  o.meshes.resize(1);
  try {  // one option per mesh (refused while the BVH is built beside the connectivity)
    Scene bad(s.meshes(), o);
    ADD_FAILURE() << "a scene with 1 mesh option for 2 meshes was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("1 mesh options for 2 meshes"), std::string::npos) << e.what();
  }
}

TEST(StaticMeshes, ALargeStaticMeshIsComparedInPiecesAndItsFirstChangeNamed) {
  // The positions given for a static mesh of several thousand vertices are compared in the
  // parallel pieces of the input: the first vertex that differs is named wherever the pieces
  // run, a coordinate that is not finite is named as such, and a refused call changes nothing.
  const AnimatedScene cloth = make_folding_cloth(12, 4);
  const TriMesh ball = make_sphere_mesh(48, 96, 0.3, Vec3(0.0, 0.0, -2.0));
  ASSERT_GT(ball.num_vertices(), 3000u);
  SceneOptions o;
  o.meshes = {MeshOptions{}, MeshOptions{.is_static = true}};
  Scene sc({cloth.meshes[0], ball}, o), fresh({cloth.meshes[0], ball}, o);
  auto message = [&](const Positions& given) {
    try {
      sc.advance(std::vector<PositionsView>{cloth.frames[1][0], given});
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  Positions moved = ball.vertices;
  moved(ball.num_vertices() - 1, 0) += 1e-12;
  moved(2100, 1) -= 1e-12;
  moved(3000, 2) += 1.0;
  EXPECT_NE(message(moved).find("the mesh is static, but vertex 2100 differs"), std::string::npos) << message(moved);
  moved(1, 1) = std::nan("");
  const std::string nan = message(moved);
  EXPECT_NE(nan.find("mesh 1 (" + ball.name + ")"), std::string::npos) << nan;
  EXPECT_EQ(nan.find("vertex 2100 differs"), std::string::npos) << nan;
  EXPECT_NE(nan.find("finite"), std::string::npos) << nan;
  // nothing changed: the next steps are a fresh scene's, given the ball's own positions or none
  for (std::size_t f = 1; f < cloth.frames.size(); ++f) {
    const StepResult a = sc.advance(std::vector<PositionsView>{cloth.frames[f][0], ball.vertices});
    const StepResult b = fresh.advance(std::vector<PositionsView>{cloth.frames[f][0], PositionsView()});
    ASSERT_EQ(a.contacts, b.contacts) << "step " << f;
  }
}

TEST(StaticMeshes, SelfCollisionOffDropsOnlyTheMeshsOwnPairs) {
  const ClothAndBall s;
  SceneOptions off;
  off.meshes = {MeshOptions{.self_collision = false}, MeshOptions{}};
  for (Method m : {Method::BruteForce, Method::Traverse, Method::Fbd}) {
    off.method = m;
    SceneOptions on = off;
    on.meshes.clear();
    Scene a(s.meshes(), off), b(s.meshes(), on);
    std::size_t dropped = 0;
    for (std::size_t f = 1; f < s.cloth.frames.size(); ++f) {
      const std::vector<PositionsView> next{s.cloth.frames[f][0], s.ball.vertices};
      const StepResult ra = a.advance(next), rb = b.advance(next);
      const std::vector<Contact> expected = without_mesh_self(rb.contacts, 0);
      ASSERT_EQ(ra.contacts, expected) << to_string(m) << " step " << f;
      dropped += rb.contacts.size() - expected.size();
    }
    EXPECT_GT(dropped, 10u) << "the folding cloth has self-contacts to drop";
  }
}
