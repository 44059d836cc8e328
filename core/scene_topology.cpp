#include <mccd/core/scene_topology.h>

#include <mccd/geometry/error.h>

namespace mccd::detail {

SceneTopology::SceneTopology(const std::vector<TriMesh>& meshes) {
  std::vector<Triangle> faces;
  for (const TriMesh& m : meshes) {
    const std::size_t off = vertex_offsets_.back();
    const std::size_t nv = off + m.num_vertices();
    if (nv >= std::size_t(1) << 31 || faces.size() + m.num_faces() >= std::size_t(1) << 30)
      throw Error("scene: too many vertices or triangles for 32-bit ids (at mesh " +
                  std::to_string(vertex_offsets_.size() - 1) + ", " + m.name + ")");
    const auto o = static_cast<std::uint32_t>(off);
    for (const Triangle& t : m.faces) faces.push_back({t[0] + o, t[1] + o, t[2] + o});
    vertex_offsets_.push_back(nv);
    face_offsets_.push_back(faces.size());
  }
  topo_ = MeshTopology(vertex_offsets_.back(), faces);
  // Edges are sorted by (max, min) global vertex, so each mesh's edges are contiguous.
  for (std::size_t m = 0; m + 1 < vertex_offsets_.size(); ++m) {
    std::size_t e = edge_offsets_.back();
    while (e < topo_.num_edges() && topo_.edges()[e][1] < vertex_offsets_[m + 1]) ++e;
    edge_offsets_.push_back(e);
  }
  carriers_ = Carriers(topo_);
  orphans_ = OrphanSet(topo_);
}

}  // namespace mccd::detail
