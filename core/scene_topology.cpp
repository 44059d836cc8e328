#include <mccd/core/scene_topology.h>

#include <mccd/geometry/error.h>
#include <mccd/geometry/large_allocator.h>

namespace mccd::detail {

SceneFaces scene_faces(const std::vector<TriMesh>& meshes) {
  SceneFaces r;
  std::size_t nf = 0;
  for (const TriMesh& m : meshes) {
    const std::size_t off = r.vertex_offsets.back();
    const std::size_t nv = off + m.num_vertices();
    nf += m.num_faces();
    if (nv >= std::size_t(1) << 31 || nf >= std::size_t(1) << 28)
      throw Error("scene: too many vertices or triangles for 32-bit ids (at mesh " +
                  std::to_string(r.vertex_offsets.size() - 1) + ", " + m.name + ")");
    r.vertex_offsets.push_back(nv);
    r.face_offsets.push_back(nf);
  }
  reserve_backed(r.faces, nf);  // written in full below
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const auto o = static_cast<std::uint32_t>(r.vertex_offsets[i]);
    for (const Triangle& t : meshes[i].faces) r.faces.push_back({t[0] + o, t[1] + o, t[2] + o});
  }
  return r;
}

SceneTopology::SceneTopology(const SceneFaces& faces, std::vector<MeshOptions> options, Representatives rule)
    : vertex_offsets_(faces.vertex_offsets),
      face_offsets_(faces.face_offsets),
      options_(std::move(options)),
      rule_(rule == Representatives::Canonical ? rule : Representatives::Leaf) {
  if (options_.empty()) options_.resize(num_meshes());
  if (options_.size() != num_meshes())
    throw Error("scene options: " + std::to_string(options_.size()) + " mesh options for " +
                std::to_string(num_meshes()) + " meshes");
  for (MeshOptions& o : options_) {
    if (o.is_static) o.self_collision = false;
    has_skipped_ = has_skipped_ || !o.self_collision;
  }
  topo_ = MeshTopology(vertex_offsets_.back(), faces.faces);
  // Edges are sorted by (max, min) global vertex, so each mesh's edges are contiguous.
  for (std::size_t m = 0; m + 1 < vertex_offsets_.size(); ++m) {
    std::size_t e = edge_offsets_.back();
    while (e < topo_.num_edges() && topo_.edges()[e][1] < vertex_offsets_[m + 1]) ++e;
    edge_offsets_.push_back(e);
  }
  auto add = [](std::vector<std::pair<std::size_t, std::size_t>>& r, std::size_t b, std::size_t e) {
    if (b == e) return;
    if (!r.empty() && r.back().second == b)
      r.back().second = e;
    else
      r.emplace_back(b, e);
  };
  for (std::size_t m = 0; m < options_.size(); ++m)
    if (!options_[m].is_static) {
      add(moving_.vertices, vertex_offsets_[m], vertex_offsets_[m + 1]);
    }
  if (rule_ != Representatives::Canonical) return;
  carriers_ = Carriers(topo_);
  orphans_ = OrphanSet(topo_);
  if (has_skipped_) orphans_.drop_if([&](std::uint32_t f) { return !options_[mesh_of_face(f)].self_collision; }, topo_);
}

}  // namespace mccd::detail
