// Hostile geometry through the public API: non-finite input refused naming the vertex and the
// frame; extreme scales, degenerate and non-manifold meshes, contacts exactly at t = 0 and
// t = 1, a vertex through an edge and through a vertex, huge motion. No crash, and every
// method reports exactly what brute force reports (which must hold the known contacts).
#include <mccd/parallel/scene.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>

#include "fixtures/scenes.h"
#include "support/errors.h"
#include <mccd/geometry/error.h>
#include <mccd/geometry/frame_sequence.h>

using namespace mccd;
using mccd::test::error_of;

namespace {

constexpr Method kMethods[] = {Method::Traverse, Method::Phc, Method::Fbd};

std::vector<PositionsView> views(const std::vector<Positions>& frame) {
  return std::vector<PositionsView>(frame.begin(), frame.end());
}

std::vector<Positions> positions_of(const std::vector<TriMesh>& meshes) {
  std::vector<Positions> out;
  for (const TriMesh& m : meshes) out.push_back(m.vertices);
  return out;
}

/// Steps start -> end, then end -> start (fbd then tracks its front once), with every method
/// and both bounding volumes, each in a fresh scene, and checks every result equals brute
/// force's. Returns brute force's first step (18-DOPs).
StepResult expect_methods_agree(const std::vector<TriMesh>& meshes, const std::vector<Positions>& start,
                                const std::vector<Positions>& end, const std::string& what) {
  StepResult first;
  for (VolumeKind volume : {VolumeKind::Kdop18, VolumeKind::Aabb}) {
    SceneOptions opt;
    opt.volume = volume;
    Scene brute(meshes, opt);
    const StepResult b1 = brute.step(views(start), views(end), Method::BruteForce);
    const StepResult b2 = brute.step(views(end), views(start), Method::BruteForce);
    if (volume == VolumeKind::Kdop18) first = b1;
    for (Method m : kMethods) {
      Scene s(meshes, opt);
      const StepResult r1 = s.step(views(start), views(end), m);
      const StepResult r2 = s.step(views(end), views(start), m);
      const std::string label = what + ", " + to_string(m) + ", " + to_string(volume);
      EXPECT_EQ(r1.contacts, b1.contacts) << label << ", forward";
      EXPECT_EQ(r2.contacts, b2.contacts) << label << ", back";
      EXPECT_EQ(r1.earliest_toi, b1.earliest_toi) << label;
    }
  }
  return first;
}

std::vector<Positions> scaled(const std::vector<Positions>& frame, double s) {
  std::vector<Positions> out = frame;
  for (Positions& p : out)
    for (double& x : p.xyz()) x *= s;
  return out;
}

bool has_vf(const StepResult& r, std::uint32_t mesh_v, std::uint32_t v, std::uint32_t mesh_f, std::uint32_t f) {
  return std::any_of(r.contacts.begin(), r.contacts.end(), [&](const Contact& c) {
    return c.kind == ContactKind::VertexFace && c.mesh_a == mesh_v && c.a == v && c.mesh_b == mesh_f && c.b == f;
  });
}

TriMesh triangle(const Vec3& a, const Vec3& b, const Vec3& c, const std::string& name) {
  TriMesh m;
  m.vertices = {a, b, c};
  m.faces = {{0, 1, 2}};
  m.name = name;
  return m;
}

/// A 2 x 2 grid of side 2 (vertices at -1, 0, 1; vertex 4 at the origin) and a small
/// triangle whose corner 0 drops from z = 0.5 through (x, y, 0) to z = -0.3; the other
/// corners stay above the grid.
struct Drop {
  std::vector<TriMesh> meshes;
  std::vector<Positions> start, end;
};
Drop drop_through(double x, double y) {
  Drop d;
  d.meshes = {make_grid_mesh(2, 2.0), triangle(Vec3(x, y, 0.5), Vec3(x + 0.1, y, 0.9), Vec3(x, y + 0.1, 0.9), "drop")};
  d.start = positions_of(d.meshes);
  d.end = d.start;
  d.end[1].mat().col(2).array() -= 0.8;  // corner 0 reaches z = 0 at t = 0.625
  return d;
}

/// The faces of `mesh` under the point (x, y) of the grid's plane (closed triangles).
std::vector<std::uint32_t> faces_under(const TriMesh& mesh, double x, double y) {
  std::vector<std::uint32_t> out;
  for (std::uint32_t f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 a = mesh.vertices.point(mesh.faces[f][0]), b = mesh.vertices.point(mesh.faces[f][1]),
               c = mesh.vertices.point(mesh.faces[f][2]);
    auto side = [&](const Vec3& p, const Vec3& q) { return (q.x() - p.x()) * (y - p.y()) - (q.y() - p.y()) * (x - p.x()); };
    const double s0 = side(a, b), s1 = side(b, c), s2 = side(c, a);
    if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) out.push_back(f);
  }
  return out;
}

}  // namespace

TEST(Hostile, NonFiniteRefusedNamingVertexAndFrame) {
  const TriMesh grid = make_grid_mesh(2);
  Scene scene({grid});
  Positions bad = grid.vertices;
  bad(4, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(error_of([&] { scene.step(bad, grid.vertices); }),
            "step start, mesh 0 (grid2): vertex 4: coordinate y is not finite (nan)");
  Positions inf = grid.vertices;
  inf(8, 2) = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(error_of([&] { scene.step(grid.vertices, inf); }),
            "step end, mesh 0 (grid2): vertex 8: coordinate z is not finite (-inf)");
  EXPECT_EQ(error_of([&] { scene.advance(bad); }), "advance, mesh 0 (grid2): vertex 4: coordinate y is not finite (nan)");
  TriMesh nan_mesh = grid;
  nan_mesh.vertices(2, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(error_of([&] { Scene({grid, nan_mesh}); }), "grid2: vertex 2: coordinate x is not finite (nan)");

  // a frame file: refused naming the file and the line of the vertex
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("mccd_hostile_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::create_directories(dir);
  std::ofstream(dir / "f0.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir / "f1.obj") << "v 0 0 0\nv 1 0 inf\nv 0 1 0\nf 1 2 3\n";
  const std::string f1 = (dir / "f1.obj").string();
  EXPECT_EQ(error_of([&] { read_frames({(dir / "f0.obj").string(), f1}); }),
            f1 + ": line 2: coordinate z of vertex 2 is not finite ('inf')");
  fs::remove_all(dir);
}

TEST(Hostile, NonFiniteInALargeMeshNamesTheFirstAndChangesNothing) {
  // Large enough that the positions are checked and copied in several parallel chunks: the
  // message still names the first bad vertex, for double and float views alike, and a refused
  // advance leaves the scene as it was.
  const TriMesh grid = make_grid_mesh(150);
  ASSERT_GT(grid.num_vertices(), 20000u);
  Scene scene({grid});
  Positions moved = grid.vertices;
  moved.mat().col(2).array() += 0.25;
  Positions bad = moved;
  bad(20000, 0) = std::numeric_limits<double>::infinity();
  bad(17000, 1) = std::numeric_limits<double>::quiet_NaN();
  const std::string name = "mesh 0 (" + grid.name + ")";
  EXPECT_EQ(error_of([&] { scene.advance(bad); }), "advance, " + name + ": vertex 17000: coordinate y is not finite (nan)");
  std::vector<float> floats(bad.data(), bad.data() + 3 * bad.rows());
  EXPECT_EQ(error_of([&] { scene.advance(PositionsView(floats)); }),
            "advance, " + name + ": vertex 17000: coordinate y is not finite (nan)");
  // The refused calls changed nothing: the next advance starts from the initial positions.
  const StepResult r = scene.advance(moved);
  Scene fresh({grid});
  const StepResult want = fresh.advance(moved);
  EXPECT_EQ(r.contacts, want.contacts);
  EXPECT_EQ(r.stats.volume_tests, want.stats.volume_tests);
  EXPECT_EQ(r.stats.front_size, want.stats.front_size);
  EXPECT_EQ(r.earliest_toi, want.earliest_toi);
  // float views are copied chunk by chunk too: the same step as from doubles.
  const std::vector<float> moved_f(moved.data(), moved.data() + 3 * moved.rows());
  Positions moved_rounded = moved;
  for (std::size_t i = 0; i < moved_f.size(); ++i) moved_rounded.data()[i] = moved_f[i];
  Scene a({grid}), b({grid});
  EXPECT_EQ(a.advance(PositionsView(moved_f)).contacts, b.advance(moved_rounded).contacts);
}

TEST(Hostile, ExtremeScalesKeepTheContact) {
  const Drop d = drop_through(0.3, -0.45);  // inside a face, clear of every edge
  const std::vector<std::uint32_t> under = faces_under(d.meshes[0], 0.3, -0.45);
  ASSERT_EQ(under.size(), 1u);
  for (double s : {1.0, 1e-30, 1e30, 1e-300, 1e300, 0x1p-1000, 0x1p+1000}) {
    std::vector<TriMesh> meshes = d.meshes;
    const std::vector<Positions> start = scaled(d.start, s), end = scaled(d.end, s);
    for (std::size_t m = 0; m < meshes.size(); ++m) meshes[m].vertices = start[m];
    char label[32];
    std::snprintf(label, sizeof label, "scale %g", s);
    const StepResult r = expect_methods_agree(meshes, start, end, label);
    EXPECT_TRUE(has_vf(r, 1, 0, 0, under[0])) << "scale " << s;
  }
}

TEST(Hostile, ZeroAreaAndNeedleTriangles) {
  // mesh 0: a needle (height 1e-12), a collinear triangle, one with two coincident corners
  TriMesh flat;
  flat.name = "degenerate";
  flat.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1e-12, 0),                   // needle
                   Vec3(0, 1, 0), Vec3(1, 1, 0), Vec3(2, 1, 0),                          // collinear
                   Vec3(0, 2, 0), Vec3(1, 2, 0), Vec3(1, 2, 0)};                         // coincident corners
  flat.faces = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  // mesh 1: three small triangles dropping a corner through the needle's inside, the
  // collinear triangle's middle, and the coincident corners
  TriMesh drops;
  drops.name = "drops";
  for (const Vec3& p : {Vec3(0.5, 2.5e-13, 0), Vec3(1.5, 1, 0), Vec3(1, 2, 0)}) {
    const auto b = static_cast<std::uint32_t>(drops.num_vertices());
    drops.vertices.xyz().insert(drops.vertices.xyz().end(),
                                {p.x(), p.y(), 0.5, p.x() + 0.1, p.y() + 0.05, 0.9, p.x() - 0.05, p.y() + 0.1, 0.9});
    drops.faces.push_back({b, b + 1, b + 2});
  }
  const std::vector<TriMesh> meshes{flat, drops};
  const std::vector<Positions> start = positions_of(meshes);
  std::vector<Positions> end = start;
  end[1].mat().col(2).array() -= 0.8;
  const StepResult r = expect_methods_agree(meshes, start, end, "degenerate");
  EXPECT_TRUE(has_vf(r, 1, 0, 0, 0)) << "through the needle";
  EXPECT_TRUE(has_vf(r, 1, 3, 0, 1)) << "through the collinear triangle";
  EXPECT_TRUE(has_vf(r, 1, 6, 0, 2)) << "through the coincident corners";
}

TEST(Hostile, CoincidentAndDuplicatedTriangles) {
  // two identical grids, one moving up through the other's place and on: every pair touches
  const TriMesh a = make_grid_mesh(3);
  TriMesh b = a;
  b.name = "copy";
  std::vector<Positions> start{a.vertices, a.vertices}, end = start;
  end[1].mat().col(2).array() += 0.5;
  StepResult r = expect_methods_agree({a, b}, start, end, "coincident grids");
  EXPECT_GE(r.contacts.size(), a.num_faces());
  // one mesh holding the same triangle three times, and a vertex passing through it
  TriMesh dup;
  dup.name = "duplicated";
  dup.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.2, 0.2, 0.5), Vec3(0.5, 0.2, 0.9),
                  Vec3(0.2, 0.5, 0.9)};
  dup.faces = {{0, 1, 2}, {0, 1, 2}, {1, 2, 0}, {3, 4, 5}};
  std::vector<Positions> s2{dup.vertices}, e2 = s2;
  for (int v = 3; v < 6; ++v) e2[0](v, 2) -= 0.8;
  r = expect_methods_agree({dup}, s2, e2, "duplicated triangles");
  for (std::uint32_t f = 0; f < 3; ++f) EXPECT_TRUE(has_vf(r, 0, 3, 0, f)) << "copy " << f;
}

TEST(Hostile, FiveFinNonManifoldEdge) {
  // five triangles around the edge (0, 1) along z; fin 0's apex swings through fin 1
  TriMesh fins;
  fins.name = "fins";
  fins.vertices = {Vec3(0, 0, 0), Vec3(0, 0, 1)};
  for (int k = 0; k < 5; ++k) {
    const double angle = 2 * std::numbers::pi * k / 5;
    fins.vertices.xyz().insert(fins.vertices.xyz().end(), {std::cos(angle), std::sin(angle), 0.5});
    fins.faces.push_back({0, 1, static_cast<std::uint32_t>(2 + k)});
  }
  std::vector<Positions> start{fins.vertices}, end = start;
  const double swing = 100.0 * std::numbers::pi / 180;  // past fin 1 at 72 degrees
  end[0].set_point(2, Vec3(std::cos(swing), std::sin(swing), 0.5));
  const StepResult r = expect_methods_agree({fins}, start, end, "five fins");
  EXPECT_TRUE(has_vf(r, 0, 2, 0, 1));
}

TEST(Hostile, IsolatedVerticesTakePartInNothing) {
  TriMesh m = make_grid_mesh(3);
  const std::size_t used = m.num_vertices();
  for (int i = 0; i < 10; ++i) m.vertices.xyz().insert(m.vertices.xyz().end(), {0.05 * i - 0.2, 0.1, 1.0});
  std::vector<Positions> start{m.vertices}, end = start;
  for (std::size_t v = used; v < m.num_vertices(); ++v) end[0](v, 2) = -1.0;  // straight through the grid
  const StepResult r = expect_methods_agree({m}, start, end, "isolated vertices");
  EXPECT_TRUE(r.contacts.empty());
}

TEST(Hostile, EmptyMeshesOneTriangleAndVerticesOnly) {
  TriMesh empty, points;
  empty.name = "empty";
  points.name = "points";
  points.vertices = {Vec3(0, 0, 0), Vec3(1, 1, 1)};
  const TriMesh grid = make_grid_mesh(2);
  std::vector<Positions> start{empty.vertices, points.vertices, grid.vertices}, end = start;
  end[1](0, 2) = -5;
  end[2].mat().col(2).array() += 0.3;
  EXPECT_TRUE(expect_methods_agree({empty, points, grid}, start, end, "empty + points + grid").contacts.empty());
  EXPECT_TRUE(expect_methods_agree({empty}, {empty.vertices}, {empty.vertices}, "empty alone").contacts.empty());
  // one triangle tumbling: it cannot touch itself
  const TriMesh one = triangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), "one");
  std::vector<Positions> s1{one.vertices}, e1{Positions{Vec3(0, 0, 1), Vec3(-1, 0, 0), Vec3(0, 0, -1)}};
  EXPECT_TRUE(expect_methods_agree({one}, s1, e1, "one triangle").contacts.empty());
}

TEST(Hostile, AllVerticesCoincident) {
  TriMesh m = make_grid_mesh(3);
  const Positions spread = m.vertices;
  for (std::size_t v = 0; v < m.num_vertices(); ++v) m.vertices.set_point(v, Vec3(0.25, -0.5, 2.0));
  const std::vector<Positions> point{m.vertices};
  expect_methods_agree({m}, point, point, "collapsed, still");
  expect_methods_agree({m}, point, {spread}, "collapsed, unfolding");
  // a second mesh passing through the collapsed one's single point
  const TriMesh blade = triangle(Vec3(-1, -1, 2.5), Vec3(2, -1, 2.5), Vec3(0, 2, 2.5), "blade");
  std::vector<Positions> start{m.vertices, blade.vertices}, end = start;
  end[1].mat().col(2).array() -= 1.0;
  const StepResult r = expect_methods_agree({m, blade}, start, end, "through the collapsed point");
  EXPECT_TRUE(has_vf(r, 0, 0, 1, 0));
}

TEST(Hostile, ContactExactlyAtStartAndEnd) {
  const TriMesh floor = triangle(Vec3(-1, -1, 0), Vec3(2, -1, 0), Vec3(-1, 2, 0), "floor");
  // corner 0 of the drop on the floor at t = 0, leaving it
  const TriMesh drop = triangle(Vec3(0.2, 0.2, 0), Vec3(0.3, 0.2, 0.4), Vec3(0.2, 0.3, 0.4), "drop");
  std::vector<Positions> start{floor.vertices, drop.vertices}, end = start;
  end[1].mat().col(2).array() += 0.5;
  StepResult r = expect_methods_agree({floor, drop}, start, end, "touching at t = 0");
  ASSERT_TRUE(has_vf(r, 1, 0, 0, 0));
  EXPECT_EQ(r.earliest_toi, 0.0);
  // corner 0 reaching the floor exactly at t = 1
  const TriMesh above = triangle(Vec3(0.2, 0.2, 0.5), Vec3(0.3, 0.2, 0.9), Vec3(0.2, 0.3, 0.9), "above");
  start = {floor.vertices, above.vertices};
  end = start;
  end[1].mat().col(2).array() -= 0.5;
  r = expect_methods_agree({floor, above}, start, end, "touching at t = 1");
  ASSERT_TRUE(has_vf(r, 1, 0, 0, 0));
  EXPECT_LE(r.earliest_toi, 1.0);
  EXPECT_GT(r.earliest_toi, 0.99);
}

TEST(Hostile, VertexThroughAnEdgeAndThroughAVertex) {
  // through the middle of the edge from (0, 0) to (1, 0): both faces beside it
  Drop d = drop_through(0.5, 0.0);
  std::vector<std::uint32_t> under = faces_under(d.meshes[0], 0.5, 0.0);
  ASSERT_EQ(under.size(), 2u);
  StepResult r = expect_methods_agree(d.meshes, d.start, d.end, "through an edge");
  for (std::uint32_t f : under) EXPECT_TRUE(has_vf(r, 1, 0, 0, f)) << "face " << f;
  // through grid vertex 4 at the origin: every face around it
  d = drop_through(0.0, 0.0);
  under = faces_under(d.meshes[0], 0.0, 0.0);
  ASSERT_GE(under.size(), 4u);
  r = expect_methods_agree(d.meshes, d.start, d.end, "through a vertex");
  for (std::uint32_t f : under) EXPECT_TRUE(has_vf(r, 1, 0, 0, f)) << "face " << f;
}

TEST(Hostile, MotionOfAMillion) {
  const AnimatedScene s = make_folding_cloth(6, 3);  // 72 triangles: torn apart, every pair overlaps
  std::vector<Positions> far = s.frames[1];
  for (Positions& p : far)
    for (std::size_t v = 0; v < p.rows(); ++v) p.set_point(v, p.point(v) + Vec3(1e6, -1e6 * (v % 3), 0.5e6 * (v % 2)));
  expect_methods_agree(s.meshes, s.frames[0], far, "cloth torn a million away");
  std::vector<Positions> one_far = s.frames[1];
  one_far[0].set_point(17, Vec3(1e6, 1e6, -1e6));
  expect_methods_agree(s.meshes, s.frames[0], one_far, "one vertex a million away");
}
