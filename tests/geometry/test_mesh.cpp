#include <mccd/geometry/mesh.h>

#include <gtest/gtest.h>

#include <mccd/geometry/topology.h>
#include "fixtures/shapes.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <mccd/geometry/error.h>
#include "support/errors.h"

using namespace mccd;

TEST(MeshTopology, GridCounts) {
  TriMesh g = make_grid_mesh(3);
  validate_mesh(g);
  MeshTopology t(g.num_vertices(), g.faces);
  EXPECT_EQ(t.num_faces(), 18u);
  // 3 rows of 4 vertices -> horizontal 4*3, vertical 4*3, diagonals 9
  EXPECT_EQ(t.num_edges(), 33u);
  EXPECT_EQ(t.num_boundary_edges(), 12u);
  EXPECT_EQ(t.num_nonmanifold_edges(), 0u);
}

TEST(MeshTopology, EdgesSortedByMaxThenMin) {
  TriMesh s = make_sphere_mesh(6, 8);
  MeshTopology t(s.num_vertices(), s.faces);
  for (std::size_t e = 1; e < t.num_edges(); ++e) {
    const Edge& a = t.edges()[e - 1];
    const Edge& b = t.edges()[e];
    EXPECT_TRUE(a[1] < b[1] || (a[1] == b[1] && a[0] < b[0]));
  }
  EXPECT_EQ(t.num_boundary_edges(), 0u);  // closed surface
  EXPECT_EQ(s.num_vertices() - t.num_edges() + t.num_faces(), 2u);  // Euler characteristic
}

TEST(MeshValidation, RefusesOutOfRangeIndex) {
  TriMesh g = make_grid_mesh(1);
  g.name = "cloth.ply";
  g.faces[1][2] = 7;
  try {
    validate_mesh(g);
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "cloth.ply: face 1: vertex index 7 out of range [0, 4)");
  }
}

namespace {

// Two triangles sharing the edge (1, 2): (0, 1, 2) and (2, 1, 3), a parallelogram strip.
TriMesh two_triangles() {
  TriMesh m;
  m.name = "pair";
  m.vertices = Positions::from_xyz({0, 0, 0, 1, 0, 0, 0.5, 1, 0, 1.5, 1, 0});
  m.faces = {{0, 1, 2}, {2, 1, 3}};
  return m;
}

using mccd::test::error_of;

}  // namespace

TEST(MeshTopology, EdgesOfTwoTriangles) {
  const TriMesh m = two_triangles();
  validate_mesh(m);
  MeshTopology t(m.num_vertices(), m.faces);
  ASSERT_EQ(t.num_vertices(), 4u);
  ASSERT_EQ(t.num_faces(), 2u);
  // sorted by (max, min): (0,1) (0,2) (1,2) (1,3) (2,3)
  const std::vector<Edge> expected{{0, 1}, {0, 2}, {1, 2}, {1, 3}, {2, 3}};
  EXPECT_EQ(t.edges(), expected);
  EXPECT_EQ(t.num_boundary_edges(), 4u);
  EXPECT_EQ(t.num_nonmanifold_edges(), 0u);
  EXPECT_EQ(t.edge_face_count(2), 2u);
  for (std::size_t e : {0u, 1u, 3u, 4u}) EXPECT_EQ(t.edge_face_count(e), 1u) << "edge " << e;
  EXPECT_EQ(t.edge_faces(2), (std::vector<std::uint32_t>{0, 1}));
  EXPECT_EQ(t.edge_faces(0), (std::vector<std::uint32_t>{0}));
  EXPECT_EQ(t.edge_faces(4), (std::vector<std::uint32_t>{1}));
}

TEST(MeshTopology, FaceEdgesFollowCorners) {
  const TriMesh m = two_triangles();
  MeshTopology t(m.num_vertices(), m.faces);
  // face 0 = (0,1,2): corners 0-1, 1-2, 2-0
  EXPECT_EQ(t.face_edges(0), (std::array<std::uint32_t, 3>{0, 2, 1}));
  // face 1 = (2,1,3): corners 2-1, 1-3, 3-2
  EXPECT_EQ(t.face_edges(1), (std::array<std::uint32_t, 3>{2, 3, 4}));
}

TEST(MeshTopology, FaceEdgesConsistentOnSphereAndGrid) {
  for (const TriMesh& m : {make_sphere_mesh(7, 9), make_grid_mesh(5)}) {
    MeshTopology t(m.num_vertices(), m.faces);
    for (std::size_t f = 0; f < m.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) {
        const auto a = m.faces[f][k], b = m.faces[f][(k + 1) % 3];
        const Edge& e = t.edges()[t.face_edges(f)[k]];
        EXPECT_EQ(e, (Edge{std::min(a, b), std::max(a, b)}));
        EXPECT_EQ(t.find_edge(a, b), t.face_edges(f)[k]);
        EXPECT_EQ(t.find_edge(b, a), t.face_edges(f)[k]);
      }
    // every edge count equals its incident faces
    std::size_t total = 0;
    for (std::size_t e = 0; e < t.num_edges(); ++e) {
      EXPECT_EQ(t.edge_faces(e).size(), t.edge_face_count(e));
      total += t.edge_face_count(e);
    }
    EXPECT_EQ(total, 3 * m.num_faces());
  }
}

TEST(MeshTopology, VertexFaces) {
  const TriMesh m = two_triangles();
  MeshTopology t(m.num_vertices(), m.faces);
  auto faces_of = [&](std::size_t v) { return std::vector<std::uint32_t>(t.vertex_faces_begin(v), t.vertex_faces_end(v)); };
  EXPECT_EQ(faces_of(0), (std::vector<std::uint32_t>{0}));
  EXPECT_EQ(faces_of(1), (std::vector<std::uint32_t>{0, 1}));
  EXPECT_EQ(faces_of(2), (std::vector<std::uint32_t>{0, 1}));
  EXPECT_EQ(faces_of(3), (std::vector<std::uint32_t>{1}));
  EXPECT_EQ(t.vertex_face_count(1), 2u);

  const TriMesh s = make_sphere_mesh(5, 6);
  MeshTopology ts(s.num_vertices(), s.faces);
  std::size_t total = 0;
  for (std::size_t v = 0; v < s.num_vertices(); ++v) {
    const std::vector<std::uint32_t> fs(ts.vertex_faces_begin(v), ts.vertex_faces_end(v));
    EXPECT_TRUE(std::is_sorted(fs.begin(), fs.end()));
    for (auto f : fs) {
      const Triangle& tri = s.faces[f];
      EXPECT_TRUE(tri[0] == v || tri[1] == v || tri[2] == v);
    }
    total += fs.size();
  }
  EXPECT_EQ(total, 3 * s.num_faces());
  EXPECT_EQ(ts.vertex_face_count(0), 6u);  // the north pole touches one fan of `segments` faces
}

TEST(MeshTopology, Adjacency) {
  TriMesh m = two_triangles();
  m.vertices.resize(7);
  m.vertices.set_point(4, Vec3(5, 5, 5));
  m.vertices.set_point(5, Vec3(6, 5, 5));
  m.vertices.set_point(6, Vec3(5, 6, 5));
  m.faces.push_back({4, 5, 6});  // disjoint
  m.faces.push_back({3, 4, 5});  // touches face 1 at vertex 3 only
  MeshTopology t(m.num_vertices(), m.faces);
  EXPECT_TRUE(t.adjacent(0, 0));
  EXPECT_TRUE(t.adjacent(0, 1));  // shared edge
  EXPECT_TRUE(t.adjacent(1, 0));
  EXPECT_FALSE(t.adjacent(0, 2));
  EXPECT_FALSE(t.adjacent(0, 3));
  EXPECT_TRUE(t.adjacent(1, 3));  // shared vertex
  EXPECT_TRUE(t.adjacent(2, 3));
}

TEST(MeshTopology, NonManifoldAndBoundaryCounts) {
  // three triangles around the edge (0, 1)
  TriMesh m;
  m.vertices = Positions::from_xyz({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1});
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  validate_mesh(m);  // non-manifold edges are accepted
  MeshTopology t(m.num_vertices(), m.faces);
  EXPECT_EQ(t.num_edges(), 7u);
  EXPECT_EQ(t.num_nonmanifold_edges(), 1u);
  EXPECT_EQ(t.num_boundary_edges(), 6u);
  const auto e01 = t.find_edge(1, 0);
  ASSERT_GE(e01, 0);
  EXPECT_EQ(t.edge_face_count(static_cast<std::size_t>(e01)), 3u);
  EXPECT_EQ(t.edge_faces(static_cast<std::size_t>(e01)), (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(t.find_edge(2, 3), -1);
  EXPECT_EQ(t.find_edge(0, 0), -1);
}

TEST(MeshTopology, EmptyMesh) {
  MeshTopology t(0, {});
  EXPECT_EQ(t.num_edges(), 0u);
  EXPECT_EQ(t.num_faces(), 0u);
  EXPECT_EQ(t.num_boundary_edges(), 0u);
  MeshTopology d;
  EXPECT_EQ(d.num_vertices(), 0u);
}

TEST(MeshValidation, RefusesRepeatedIndex) {
  TriMesh m = two_triangles();
  m.faces[1] = {3, 1, 3};
  EXPECT_EQ(error_of([&] { validate_mesh(m); }), "pair: face 1: repeated vertex index (3, 1, 3)");
}

TEST(MeshValidation, RefusesNonFiniteCoordinates) {
  TriMesh m = two_triangles();
  m.vertices(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(error_of([&] { validate_mesh(m); }).find("pair: vertex 2: coordinate y is not finite"), std::string::npos);
  m.vertices(2, 1) = 0;
  m.vertices(3, 2) = -std::numeric_limits<double>::infinity();
  EXPECT_NE(error_of([&] { validate_mesh(m); }).find("pair: vertex 3: coordinate z is not finite"), std::string::npos);
}

TEST(MeshValidation, UnnamedMeshIsCalledMesh) {
  TriMesh m = two_triangles();
  m.name.clear();
  m.faces[0][0] = 4;
  EXPECT_EQ(error_of([&] { validate_mesh(m); }), "mesh: face 0: vertex index 4 out of range [0, 4)");
}

TEST(MeshValidation, AcceptsZeroAreaTriangles) {
  TriMesh m = two_triangles();
  m.vertices.set_point(3, m.vertices.point(1));  // face 1 collapses to a segment
  EXPECT_NO_THROW(validate_mesh(m));
  EXPECT_EQ(count_zero_area_faces(m), 1u);
  m.vertices.set_point(2, Vec3(2, 0, 0));  // now both are collinear
  EXPECT_EQ(count_zero_area_faces(m), 2u);
  EXPECT_EQ(count_zero_area_faces(two_triangles()), 0u);
}

TEST(MeshValidation, PositionsRowCountAndFinite) {
  Positions p = Positions(3);
  EXPECT_NO_THROW(validate_positions(p, 3, "frame 1"));
  EXPECT_EQ(error_of([&] { validate_positions(p, 4, "frame 1 (a.ply)"); }),
            "frame 1 (a.ply): has 3 vertices, expected 4");
  p(1, 0) = std::numeric_limits<double>::infinity();
  EXPECT_NE(error_of([&] { validate_positions(p, 3, "frame 1"); }).find("frame 1: vertex 1: coordinate x is not finite"),
            std::string::npos);
}

// The dense pass (blocks of points into running bounds of their own, then the last points) is
// the point-by-point box, for every count around its block and every coordinate's extremes.
TEST(MeshBounds, BoundingBoxOfEveryCountIsThePointByPointBox) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-100, 100);
  for (std::size_t n = 0; n <= 41; ++n) {
    std::vector<double> xyz(3 * n);
    for (double& x : xyz) x = u(rng);
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::size_t v = 0; v < n; ++v)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], xyz[3 * v + k]);
        hi[k] = std::max(hi[k], xyz[3 * v + k]);
      }
    const Bounds3 b = bounding_box(PositionsView(xyz.data(), n));
    EXPECT_EQ(b.min, lo) << n << " points";
    EXPECT_EQ(b.max, hi) << n << " points";
  }
}

TEST(MeshBounds, BoundingBox) {
  const TriMesh m = two_triangles();
  const Bounds3 b = bounding_box(m.vertices);
  EXPECT_EQ(b.min, Vec3(0, 0, 0));
  EXPECT_EQ(b.max, Vec3(1.5, 1, 0));
  const Positions none;
  const Bounds3 e = bounding_box(none);
  EXPECT_EQ(e.min.x(), std::numeric_limits<double>::infinity());
  EXPECT_EQ(e.max.z(), -std::numeric_limits<double>::infinity());
  const TriMesh sphere = make_sphere_mesh(8, 8, 2.0, Vec3(1, 2, 3));
  const Bounds3 s = bounding_box(sphere.vertices);
  EXPECT_DOUBLE_EQ(s.min.z(), 1.0);
  EXPECT_DOUBLE_EQ(s.max.z(), 5.0);
}
