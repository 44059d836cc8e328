#pragma once
/// @file Internal: the static data of a scene, independent of the bounding volume. All meshes
/// as one triangle list with global vertex, face and edge ids (each mesh's ids contiguous), its
/// connectivity, the carrier rule and the orphan set.
#include <algorithm>
#include <cstdint>
#include <vector>

#include <mccd/core/carriers.h>
#include <mccd/core/orphans.h>
#include <mccd/geometry/topology.h>

namespace mccd::detail {

class SceneTopology {
 public:
  SceneTopology() = default;
  /// From validated meshes. Throws mccd::Error when the ids do not fit in 32 bits.
  explicit SceneTopology(const std::vector<TriMesh>& meshes);
  SceneTopology(const SceneTopology&) = delete;  // the carriers point into topo_
  SceneTopology& operator=(const SceneTopology&) = delete;

  const MeshTopology& topology() const { return topo_; }
  const Carriers& carriers() const { return carriers_; }
  const OrphanSet& orphans() const { return orphans_; }
  std::size_t num_meshes() const { return vertex_offsets_.size() - 1; }

  std::size_t vertex_offset(std::size_t mesh) const { return vertex_offsets_[mesh]; }
  std::size_t face_offset(std::size_t mesh) const { return face_offsets_[mesh]; }
  std::size_t edge_offset(std::size_t mesh) const { return edge_offsets_[mesh]; }
  std::uint32_t mesh_of_vertex(std::size_t v) const { return mesh_of(v, vertex_offsets_); }
  std::uint32_t mesh_of_face(std::size_t f) const { return mesh_of(f, face_offsets_); }
  std::uint32_t mesh_of_edge(std::size_t e) const { return mesh_of(e, edge_offsets_); }

 private:
  static std::uint32_t mesh_of(std::size_t id, const std::vector<std::size_t>& offsets) {
    return static_cast<std::uint32_t>(std::upper_bound(offsets.begin(), offsets.end(), id) - offsets.begin() - 1);
  }
  std::vector<std::size_t> vertex_offsets_{0}, face_offsets_{0}, edge_offsets_{0};
  MeshTopology topo_;
  Carriers carriers_;
  OrphanSet orphans_;
};

}  // namespace mccd::detail
