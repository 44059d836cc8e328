#pragma once
/// @file Triangle meshes with double positions, and their validation.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <mccd/geometry/positions.h>

namespace mccd {

/// A triangle: three vertex indices into its mesh, counter-clockwise.
using Triangle = std::array<std::uint32_t, 3>;
/// An undirected edge, stored as (min, max) vertex index.
using Edge = std::array<std::uint32_t, 2>;

/// A triangle mesh: positions and the triangle list. `name` is used in error messages
/// (a file name or "mesh 2").
struct TriMesh {
  Positions vertices;
  std::vector<Triangle> faces;
  std::string name;

  std::size_t num_vertices() const { return vertices.rows(); }
  std::size_t num_faces() const { return faces.size(); }
};

/// Checks a mesh: every index in range, no face with a repeated index, every coordinate
/// finite. Throws mccd::Error naming the mesh, the face or vertex, and the problem.
/// Zero-area triangles and non-manifold edges are accepted.
void validate_mesh(const TriMesh& mesh);

/// Checks that a position array is usable for a mesh of `num_vertices` vertices: 3 columns,
/// the right row count and only finite values. `what` names the array in the message
/// ("frame 3 (cloth93.ply)"). Throws mccd::Error.
void validate_positions(const PositionsView& positions, std::size_t num_vertices, const std::string& what);
/// The same checks less the values' finiteness (what a caller that checks the values in
/// parallel calls first).
void validate_positions_shape(const PositionsView& positions, std::size_t num_vertices, const std::string& what);

/// Number of faces of `mesh` whose area is exactly zero in double arithmetic
/// (|cross product| == 0: repeated positions or collinear corners).
std::size_t count_zero_area_faces(const TriMesh& mesh);

/// Axis-aligned bounds of the vertices; an empty array gives min = +inf, max = -inf.
struct Bounds3 {
  Vec3 min, max;
};
Bounds3 bounding_box(const PositionsView& positions);

}  // namespace mccd
