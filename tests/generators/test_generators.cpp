// The benchmark scene generators: frame counts and sizes, determinism (seed, thread count),
// the physics they promise (the cloth stays outside the ball, bodies stay rigid and boxed),
// and the scene cache (re-used when current, regenerated when stale, nothing half-written).
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <unistd.h>

#include <mccd/geometry/error.h>
#include <mccd/geometry/mesh_io.h>

#include "fixtures/drape.h"
#include "generators/generators.h"
#include "generators/scene_cache.h"

using namespace mccd;
using namespace mccd::gen;
namespace fs = std::filesystem;

namespace {

struct Captured {
  TriMesh first;
  std::vector<Positions> frames;
  bool same_faces = true;
};

Captured capture(const std::string& name, SceneSize size, std::uint64_t seed, const nlohmann::json& overrides = nlohmann::json::object()) {
  const Generator& g = find_generator(name);
  nlohmann::json p = g.parameters(size);
  if (!overrides.empty()) p.update(overrides);
  Captured c;
  g.run(p, seed, [&](int f, const TriMesh& mesh) {
    EXPECT_EQ(f, int(c.frames.size()));
    if (f == 0) c.first = mesh;
    c.same_faces = c.same_faces && mesh.faces == c.first.faces;
    c.frames.push_back(mesh.vertices);
  });
  return c;
}

// A fresh folder under the test's temporary directory.
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(testing::TempDir()) / ("mccd_gen_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

}  // namespace

TEST(Generators, EveryTinySceneIsAValidMeshSequence) {
  for (const Generator& g : generators()) {
    const Captured c = capture(g.name, SceneSize::Tiny, 1);
    ASSERT_EQ(int(c.frames.size()), int(g.parameters(SceneSize::Tiny).at("frames"))) << g.name;
    EXPECT_TRUE(c.same_faces) << g.name << ": the triangles change between frames";
    EXPECT_GT(c.first.num_faces(), 50u) << g.name;
    for (std::size_t f = 0; f < c.frames.size(); ++f) {
      TriMesh m = c.first;
      m.vertices = c.frames[f];
      EXPECT_NO_THROW(validate_mesh(m)) << g.name << " frame " << f;
    }
    EXPECT_FALSE(c.frames.front() == c.frames.back()) << g.name << ": nothing moves";
  }
}

TEST(Generators, FullSizesAreThePapers) {
  // frame 0 only: the meshes, without the simulation
  const std::map<std::string, std::pair<std::size_t, std::size_t>> expected{
      {"cloth-ball", {88000, 96000}}, {"n-body", {32000, 36000}}, {"bart", {4000, 4000}}, {"skirt", {40000, 50000}}};
  for (const Generator& g : generators()) {
    EXPECT_GE(int(g.parameters(SceneSize::Full).at("frames")), 90) << g.name;
    const Captured c = capture(g.name, SceneSize::Full, 1, {{"frames", 1}});
    const auto [lo, hi] = expected.at(g.name);
    EXPECT_GE(c.first.num_faces(), lo) << g.name;
    EXPECT_LE(c.first.num_faces(), hi) << g.name;
  }
}

TEST(Generators, DeterministicFromTheSeedOnAnyThreadCount) {
  for (const char* name : {"cloth-ball", "n-body", "bart", "skirt"}) {
    Captured one, two;
    tbb::task_arena(1).execute([&] { one = capture(name, SceneSize::Tiny, 7); });
    tbb::task_arena(2).execute([&] { two = capture(name, SceneSize::Tiny, 7); });
    EXPECT_TRUE(one.frames == two.frames) << name << ": differs between 1 and 2 threads";
    const Captured other = capture(name, SceneSize::Tiny, 8);
    EXPECT_FALSE(one.frames.back() == other.frames.back()) << name << ": the seed changes nothing";
  }
}

TEST(DrapeFixture, SameFramesOnAnyThreadCountWithTheClothOutsideTheBall) {
  // 140 x 140 quads: links enough per colour for the sweeps to run in parallel chunks
  AnimatedScene one, two;
  tbb::task_arena(1).execute([&] { one = make_cloth_on_ball(140, 8, 4); });
  tbb::task_arena(2).execute([&] { two = make_cloth_on_ball(140, 8, 4); });
  ASSERT_EQ(one.frames.size(), 4u);
  ASSERT_EQ(two.frames.size(), 4u);
  for (std::size_t f = 0; f < one.frames.size(); ++f)
    EXPECT_TRUE(one.frames[f][0] == two.frames[f][0]) << "frame " << f << ": differs between 1 and 2 threads";
  const Positions& last = one.frames.back()[0];
  double top0 = -1e9, top1 = -1e9;
  for (std::size_t i = 0; i < last.rows(); ++i) {
    ASSERT_GE(last.point(i).norm(), 0.5 * (1 - 1e-12)) << "vertex " << i << " inside the ball";
    top0 = std::max(top0, one.frames.front()[0](i, 2));
    top1 = std::max(top1, last(i, 2));
  }
  EXPECT_LT(top1, top0) << "the cloth does not fall";
}

TEST(Generators, ClothStaysOutsideTheBallAndFalls) {
  const nlohmann::json p = cloth_ball_parameters(SceneSize::Tiny);
  const Captured c = capture("cloth-ball", SceneSize::Tiny, 3);
  const int n = p.at("quads_per_side");
  const std::size_t cloth_vertices = std::size_t(n + 1) * (n + 1);
  const double r = p.at("ball_radius");
  for (std::size_t f = 0; f < c.frames.size(); ++f)
    for (std::size_t i = 0; i < cloth_vertices; ++i) ASSERT_GE(c.frames[f].point(i).norm(), r) << "frame " << f << " vertex " << i;
  double top0 = -1e9, top1 = -1e9;
  for (std::size_t i = 0; i < cloth_vertices; ++i)
    top0 = std::max(top0, c.frames.front()(i, 2)), top1 = std::max(top1, c.frames.back()(i, 2));
  EXPECT_LT(top1, top0) << "the cloth does not fall";
}

TEST(Generators, BodiesAreRigidAndStayInTheBox) {
  const nlohmann::json p = n_body_parameters(SceneSize::Tiny);
  const Captured c = capture("n-body", SceneSize::Tiny, 5);
  const double half = p.at("box_half_side");
  for (const Positions& f : c.frames)
    for (std::size_t i = 0; i < f.rows(); ++i) ASSERT_LE(f.point(i).cwiseAbs().maxCoeff(), half * 1.001) << i;
  // the first body is a sphere: its pairwise vertex distances never change
  for (std::size_t f = 1; f < c.frames.size(); ++f)
    for (std::size_t i = 1; i < 10; ++i)
      EXPECT_NEAR((c.frames[f].point(i) - c.frames[f].point(0)).norm(), (c.frames[0].point(i) - c.frames[0].point(0)).norm(),
                  1e-9);
}

TEST(Generators, UnknownNamesAreRefused) {
  try {
    find_generator("teapot");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cloth-ball, n-body, bart, skirt"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_size("huge"), Error);
  EXPECT_EQ(parse_size("small"), SceneSize::Small);
}

TEST(SceneCache, WrittenOnceThenReusedAndRegeneratedWhenStale) {
  const fs::path cache = scratch("cache");
  const CachedScene a = ensure_scene("bart", SceneSize::Tiny, 2, cache.string());
  EXPECT_TRUE(a.generated);
  ASSERT_EQ(a.frames.size(), 6u);
  for (const std::string& f : a.frames) EXPECT_TRUE(fs::is_regular_file(f)) << f;
  EXPECT_EQ(read_mesh(a.frames[0]).num_faces(), a.triangles);
  const auto stamp = fs::last_write_time(a.frames[3]);

  const CachedScene b = ensure_scene("bart", SceneSize::Tiny, 2, cache.string());
  EXPECT_FALSE(b.generated);
  EXPECT_EQ(b.frames, a.frames);
  EXPECT_EQ(fs::last_write_time(a.frames[3]), stamp);

  // another seed: another folder; an older generator version or a missing frame: regenerated
  EXPECT_NE(ensure_scene("bart", SceneSize::Tiny, 3, cache.string()).dir, a.dir);
  const fs::path manifest = fs::path(a.dir) / "manifest.json";
  nlohmann::json m = nlohmann::json::parse(std::ifstream(manifest));
  m["generator_version"] = 0;
  std::ofstream(manifest) << m.dump();
  EXPECT_TRUE(ensure_scene("bart", SceneSize::Tiny, 2, cache.string()).generated);
  fs::remove(a.frames[4]);
  EXPECT_TRUE(ensure_scene("bart", SceneSize::Tiny, 2, cache.string()).generated);
  EXPECT_TRUE(fs::is_regular_file(a.frames[4]));
  EXPECT_FALSE(ensure_scene("bart", SceneSize::Tiny, 2, cache.string()).generated);

  for (const auto& entry : fs::directory_iterator(cache))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
  fs::remove_all(cache);
}
