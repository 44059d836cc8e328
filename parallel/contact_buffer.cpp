#include <mccd/parallel/contact_buffer.h>

#include <algorithm>
#include <limits>
#include <vector>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_sort.h>

namespace mccd::detail {

void join_contacts(const ContactBuffer& buffer, JoinScratch& scratch, const SceneTopology& scene, StepResult& res,
                   bool allow_packed) {
  const std::size_t n = buffer.size();
  const bool large = n > kParallelJoin;
  // The contacts' positions in the canonical order (the keys are unique, so any sort gives it).
  const MeshTopology& topo = scene.topology();
  const std::size_t ids = std::max({topo.num_vertices(), topo.num_faces(), topo.num_edges(), std::size_t(1)});
  const auto id_bits = static_cast<unsigned>(std::bit_width(ids - 1));
  struct Keys {  // the buffer's keys in sequence
    ContactBuffer::const_iterator it;
    std::uint64_t operator*() const { return it->key; }
    Keys& operator++() { return ++it, *this; }
    Keys operator+(std::ptrdiff_t i) const { return {it + i}; }
  };
  const bool packed =
      allow_packed && packed_key_order(Keys{buffer.begin()}, n, id_bits, scratch.order, &scratch.counts);
  const std::uint64_t pos_mask = (std::uint64_t(1) << position_bits(n)) - 1;
  if (!packed) {
    scratch.raw.assign(buffer.begin(), buffer.end());
    auto before = [](const RawContact& x, const RawContact& y) { return x.key < y.key; };
    if (large)
      tbb::parallel_sort(scratch.raw.begin(), scratch.raw.end(), before);
    else
      std::sort(scratch.raw.begin(), scratch.raw.end(), before);
  }
  auto raw = [&](std::size_t i) -> const RawContact& {
    return packed ? buffer[scratch.order[i] & pos_mask] : scratch.raw[i];
  };
  reserve_huge(res.contacts, n, /*populate=*/!large);
  if (large) {
    // A fresh array every step (it is the caller's): its pages backed in parallel, 64 KiB at a
    // time (one fault per page, serially, was most of the join's time on many threads).
    auto* bytes = reinterpret_cast<unsigned char*>(res.contacts.data());
    dynamic_for(n * sizeof(Contact), std::size_t(1) << 16,
                [&](std::size_t b, std::size_t e) { populate_pages(bytes + b, e - b); });
  }
  res.contacts.resize(n);
  // Converted by chunks, each counting its kinds and its earliest time of impact (added up in
  // chunk order afterwards: counts and a minimum do not depend on it).
  const std::size_t per_chunk = std::clamp<std::size_t>(n / 64, 256, 4096);
  struct Tally {
    std::uint64_t vf = 0, ee = 0;
    double earliest = std::numeric_limits<double>::infinity();
  };
  std::vector<Tally> tallies((n + per_chunk - 1) / per_chunk);
  auto convert = [&](std::size_t chunk) {
    Tally& t = tallies[chunk];
    // The packed order reads the buffer at random: each record a cache miss unless asked for
    // ahead (16 records ahead hid most of the latency).
    constexpr std::size_t kAhead = 16;
    for (std::size_t i = chunk * per_chunk, end = std::min(n, i + per_chunk); i != end; ++i) {
      if (i + kAhead < end) __builtin_prefetch(&raw(i + kAhead));
      const RawContact& r = raw(i);
      ++(r.kind() == ContactKind::VertexFace ? t.vf : t.ee);
      t.earliest = std::min(t.earliest, r.toi);
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
    for_each_index(tallies.size(), convert, tbb::auto_partitioner());
  else
    for (std::size_t c = 0; c < tallies.size(); ++c) convert(c);
  for (const Tally& t : tallies) {
    res.stats.vf_contacts += t.vf;
    res.stats.ee_contacts += t.ee;
    res.earliest_toi = std::min(res.earliest_toi, t.earliest);
  }
}

}  // namespace mccd::detail
