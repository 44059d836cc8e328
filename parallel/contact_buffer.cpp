#include <mccd/parallel/contact_buffer.h>

#include <algorithm>

#include <oneapi/tbb/parallel_sort.h>

namespace mccd::detail {

void join_contacts(const ContactBuffer& buffer, const SceneTopology& scene, StepResult& res) {
  // Global ids number the meshes in order, so (kind, global a, global b) is the canonical
  // order (kind, mesh a, a, mesh b, b); the raw records are smaller to sort. Keys are unique
  // (one contact per feature pair), so any sort gives the same order.
  std::vector<RawContact> raw(buffer.begin(), buffer.end());
  auto before = [](const RawContact& x, const RawContact& y) {
    if (x.kind != y.kind) return x.kind < y.kind;
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  };
  if (raw.size() > 4096)
    tbb::parallel_sort(raw.begin(), raw.end(), before);
  else
    std::sort(raw.begin(), raw.end(), before);
  res.contacts.clear();
  res.contacts.reserve(raw.size());
  for (const RawContact& r : raw) {
    Contact c{};
    c.kind = r.kind;
    c.toi = r.toi;
    if (r.kind == ContactKind::VertexFace) {
      c.mesh_a = scene.mesh_of_vertex(r.a);
      c.a = static_cast<std::uint32_t>(r.a - scene.vertex_offset(c.mesh_a));
      c.mesh_b = scene.mesh_of_face(r.b);
      c.b = static_cast<std::uint32_t>(r.b - scene.face_offset(c.mesh_b));
      ++res.stats.vf_contacts;
    } else {
      c.mesh_a = scene.mesh_of_edge(r.a);
      c.a = static_cast<std::uint32_t>(r.a - scene.edge_offset(c.mesh_a));
      c.mesh_b = scene.mesh_of_edge(r.b);
      c.b = static_cast<std::uint32_t>(r.b - scene.edge_offset(c.mesh_b));
      const Edge& ea = scene.topology().edges()[r.a];
      const Edge& eb = scene.topology().edges()[r.b];
      const auto va = static_cast<std::uint32_t>(scene.vertex_offset(c.mesh_a));
      const auto vb = static_cast<std::uint32_t>(scene.vertex_offset(c.mesh_b));
      c.a_vertices = {ea[0] - va, ea[1] - va};
      c.b_vertices = {eb[0] - vb, eb[1] - vb};
      ++res.stats.ee_contacts;
    }
    res.earliest_toi = std::min(res.earliest_toi, c.toi);
    res.contacts.push_back(c);
  }
}

}  // namespace mccd::detail
