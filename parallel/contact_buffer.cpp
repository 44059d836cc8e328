#include <mccd/parallel/contact_buffer.h>

#include <algorithm>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_sort.h>

namespace mccd::detail {

void join_contacts(const ContactBuffer& buffer, LargeVector<RawContact>& raw, const SceneTopology& scene,
                   StepResult& res) {
  // The keys order the contacts canonically (worker_output.h) and are unique (one contact per
  // feature pair), so any sort gives the same order.
  raw.assign(buffer.begin(), buffer.end());
  auto before = [](const RawContact& x, const RawContact& y) { return x.key < y.key; };
  const bool large = raw.size() > 4096;
  if (large)
    tbb::parallel_sort(raw.begin(), raw.end(), before);
  else
    std::sort(raw.begin(), raw.end(), before);
  res.contacts.reserve(raw.size());
  advise_huge_pages(res.contacts.data(), raw.size() * sizeof(Contact));
  res.contacts.resize(raw.size());
  auto convert = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i != end; ++i) {
      const RawContact& r = raw[i];
      Contact& c = res.contacts[i];
      c.kind = r.kind();
      c.toi = r.toi;
      const std::uint32_t a = r.a(), b = r.b();
      if (c.kind == ContactKind::VertexFace) {
        c.mesh_a = scene.mesh_of_vertex(a);
        c.a = static_cast<std::uint32_t>(a - scene.vertex_offset(c.mesh_a));
        c.mesh_b = scene.mesh_of_face(b);
        c.b = static_cast<std::uint32_t>(b - scene.face_offset(c.mesh_b));
        c.a_vertices = c.b_vertices = {0, 0};
      } else {
        c.mesh_a = scene.mesh_of_edge(a);
        c.a = static_cast<std::uint32_t>(a - scene.edge_offset(c.mesh_a));
        c.mesh_b = scene.mesh_of_edge(b);
        c.b = static_cast<std::uint32_t>(b - scene.edge_offset(c.mesh_b));
        const auto va = static_cast<std::uint32_t>(scene.vertex_offset(c.mesh_a));
        const auto vb = static_cast<std::uint32_t>(scene.vertex_offset(c.mesh_b));
        c.a_vertices = {r.vertices[0] - va, r.vertices[1] - va};
        c.b_vertices = {r.vertices[2] - vb, r.vertices[3] - vb};
      }
    }
  };
  if (large)
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, raw.size(), 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) { convert(r.begin(), r.end()); });
  else
    convert(0, raw.size());
  for (const RawContact& r : raw) {
    ++(r.kind() == ContactKind::VertexFace ? res.stats.vf_contacts : res.stats.ee_contacts);
    res.earliest_toi = std::min(res.earliest_toi, r.toi);
  }
}

}  // namespace mccd::detail
