#pragma once
/// @file Connectivity of a triangle list: unique edges, vertex and edge to face incidence,
/// adjacency.
#include <array>
#include <cstdint>
#include <vector>

#include <mccd/geometry/mesh.h>

namespace mccd {

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
  std::vector<std::uint32_t> edge_faces(std::size_t e) const { return {edge_faces_begin(e), edge_faces_end(e)}; }
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

}  // namespace mccd
