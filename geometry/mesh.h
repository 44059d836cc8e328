#pragma once
/// @file Triangle meshes with double positions, and their connectivity.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace mccd {

using Vec3 = Eigen::Vector3d;
/// Vertex positions, one row (x, y, z) per vertex, row-major so a frame is one flat array.
using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
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

  std::size_t num_vertices() const { return static_cast<std::size_t>(vertices.rows()); }
  std::size_t num_faces() const { return faces.size(); }
};

/// Checks a mesh: every index in range, no face with a repeated index, every coordinate
/// finite. Throws mccd::Error naming the mesh, the face or vertex, and the problem.
/// Zero-area triangles and non-manifold edges are accepted.
void validate_mesh(const TriMesh& mesh);

/// Checks that a position array is usable for a mesh of `num_vertices` vertices: right
/// row count and only finite values. `what` names the array in the message
/// ("frame 3 (cloth93.ply)"). Throws mccd::Error.
void validate_positions(const Eigen::Ref<const Positions>& positions, std::size_t num_vertices,
                        const std::string& what);

/// Connectivity of one triangle list, computed once. Immutable afterwards; all queries
/// are thread safe.
///
/// Edges are the unique undirected edges of the faces, stored (min, max) and sorted by
/// (max, min): the order libigl's `edges()` produces, so edge ids match the public
/// Time-of-Impact data set.
class MeshTopology {
 public:
  MeshTopology() = default;
  /// Builds connectivity for `faces` over `num_vertices` vertices. The faces must already be
  /// valid (see validate_mesh).
  MeshTopology(std::size_t num_vertices, const std::vector<Triangle>& faces);

  std::size_t num_vertices() const { return vertex_face_offsets_.empty() ? 0 : vertex_face_offsets_.size() - 1; }
  std::size_t num_faces() const { return faces_.size(); }
  std::size_t num_edges() const { return edges_.size(); }

  const std::vector<Triangle>& faces() const { return faces_; }
  const std::vector<Edge>& edges() const { return edges_; }
  /// The three edge ids of face f: edge k joins corners k and (k+1)%3.
  const std::array<std::uint32_t, 3>& face_edges(std::size_t f) const { return face_edges_[f]; }

  /// Faces incident to vertex v, ascending.
  const std::uint32_t* vertex_faces_begin(std::size_t v) const { return vertex_faces_.data() + vertex_face_offsets_[v]; }
  const std::uint32_t* vertex_faces_end(std::size_t v) const { return vertex_faces_.data() + vertex_face_offsets_[v + 1]; }
  std::size_t vertex_face_count(std::size_t v) const { return vertex_face_offsets_[v + 1] - vertex_face_offsets_[v]; }

  /// Number of faces around edge e (1: boundary, 2: interior, more: non-manifold).
  std::uint32_t edge_face_count(std::size_t e) const { return edge_face_offsets_[e + 1] - edge_face_offsets_[e]; }
  /// Faces incident to edge e, ascending.
  std::vector<std::uint32_t> edge_faces(std::size_t e) const {
    return {edge_faces_begin(e), edge_faces_end(e)};
  }
  const std::uint32_t* edge_faces_begin(std::size_t e) const { return edge_faces_.data() + edge_face_offsets_[e]; }
  const std::uint32_t* edge_faces_end(std::size_t e) const { return edge_faces_.data() + edge_face_offsets_[e + 1]; }

  /// Whether two faces share at least one vertex (a face is adjacent to itself).
  bool adjacent(std::size_t f, std::size_t g) const {
    const Triangle& a = faces_[f];
    const Triangle& b = faces_[g];
    for (auto x : a)
      for (auto y : b)
        if (x == y) return true;
    return false;
  }

  std::size_t num_boundary_edges() const;
  std::size_t num_nonmanifold_edges() const;
  /// Edge id of (a, b) in either order, or -1 when no face has that edge.
  std::int64_t find_edge(std::uint32_t a, std::uint32_t b) const;

 private:
  std::vector<Triangle> faces_;
  std::vector<Edge> edges_;
  std::vector<std::array<std::uint32_t, 3>> face_edges_;
  std::vector<std::uint32_t> edge_face_offsets_;  // CSR: faces of edge e, ascending
  std::vector<std::uint32_t> edge_faces_;
  std::vector<std::uint32_t> vertex_face_offsets_;
  std::vector<std::uint32_t> vertex_faces_;
};

/// Number of faces of `mesh` whose area is exactly zero in double arithmetic
/// (|cross product| == 0: repeated positions or collinear corners).
std::size_t count_zero_area_faces(const TriMesh& mesh);

/// Axis-aligned bounds of the vertices; an empty mesh gives min = +inf, max = -inf.
struct Bounds3 {
  Vec3 min, max;
};
Bounds3 bounding_box(const Eigen::Ref<const Positions>& positions);

/// Built-in meshes for demos and tests.
/// A square cloth of `n` x `n` quads (2 n^2 triangles) in the z = 0 plane, side `size`,
/// centred on the origin.
TriMesh make_grid_mesh(int n, double size = 1.0);
/// A UV sphere of radius r with `rings` latitude bands and `segments` longitude segments.
TriMesh make_sphere_mesh(int rings, int segments, double radius = 1.0, const Vec3& centre = Vec3::Zero());

}  // namespace mccd
