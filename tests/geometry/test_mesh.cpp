#include "geometry/mesh.h"

#include <gtest/gtest.h>

#include "geometry/error.h"

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
