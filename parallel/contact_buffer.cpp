#include <mccd/parallel/contact_buffer.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <vector>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_sort.h>

namespace mccd::detail {

namespace {

/// The kinds and the earliest time of impact of a run of contacts: sums and a minimum, the
/// same whatever runs the contacts are cut into and in whatever order they are added up.
struct Tally {
  std::atomic<std::uint64_t> vf{0}, ee{0};
  std::atomic<double> earliest{std::numeric_limits<double>::infinity()};

  void add(std::uint64_t v, std::uint64_t e, double t) {
    vf.fetch_add(v, std::memory_order_relaxed);
    ee.fetch_add(e, std::memory_order_relaxed);
    double m = earliest.load(std::memory_order_relaxed);
    while (t < m && !earliest.compare_exchange_weak(m, t, std::memory_order_relaxed)) {
    }
  }
};

/// Contacts [begin, end) of the canonical order into `out` (raw(i): the i-th raw record in
/// that order), tallied.
template <class Raw>
void convert(const Raw& raw, std::size_t begin, std::size_t end, const SceneTopology& scene, std::vector<Contact>& out,
             Tally& tally) {
  std::uint64_t vf = 0, ee = 0;
  double earliest = std::numeric_limits<double>::infinity();
  // The packed order reads the buffer at random: each record a cache miss unless asked for
  // ahead (16 records ahead hid most of the latency).
  constexpr std::size_t kAhead = 16;
  for (std::size_t i = begin; i != end; ++i) {
    if (i + kAhead < end) __builtin_prefetch(&raw(i + kAhead));
    const RawContact& r = raw(i);
    ++(r.kind() == ContactKind::VertexFace ? vf : ee);
    earliest = std::min(earliest, r.toi);
    Contact& c = out[i];
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
  tally.add(vf, ee, earliest);
}

}  // namespace

void join_contacts(const ContactBuffer& buffer, JoinScratch& scratch, const SceneTopology& scene, StepResult& res,
                   bool allow_packed, bool kept) {
  const std::size_t n = buffer.size();
  const bool large = n > kParallelJoin;
  // The result's storage, made ready beside the counting of the order: the contacts are
  // converted into it as the sort finishes each part of the order, in the sort's own loop.
  std::vector<Contact>& out = res.contacts;
  auto prepare = [&] {
    if (!kept || out.capacity() < n) {
      // A fresh array (it is the caller's); a large one's pages backed in parallel, 64 KiB at
      // a time (one fault per page, serially, was most of the join's time on many threads),
      // and each page then written once there: in a virtual machine whose host maps a page
      // only at the first write from the process, the serial resize below took those faults.
      out = std::vector<Contact>();
      reserve_huge(out, kept ? n + n / 4 : n, /*populate=*/false);
      auto* bytes = reinterpret_cast<unsigned char*>(out.data());
      if (large)
        dynamic_for(n * sizeof(Contact), std::size_t(1) << 16, [&](std::size_t b, std::size_t e) {
          populate_pages(bytes + b, e - b);
          for (std::size_t p = b; p < e; p += 4096) bytes[p] = 0;  // zero: what resize writes
        });
    }
    out.resize(n);  // a kept list: only what lies past its old end is initialised
  };
  Tally tally;
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
  const std::uint64_t pos_mask = (std::uint64_t(1) << position_bits(n)) - 1;
  auto packed_raw = [&](std::size_t i) -> const RawContact& { return buffer[scratch.order[i] & pos_mask]; };
  const bool packed =
      allow_packed &&
      packed_key_order(
          Keys{buffer.begin()}, n, id_bits, scratch.order, &scratch.counts,
          [&](std::size_t b, std::size_t e) { convert(packed_raw, b, e, scene, out, tally); }, prepare);
  if (!allow_packed) prepare();
  if (!packed) {
    scratch.raw.assign(buffer.begin(), buffer.end());
    auto before = [](const RawContact& x, const RawContact& y) { return x.key < y.key; };
    if (large)
      tbb::parallel_sort(scratch.raw.begin(), scratch.raw.end(), before);
    else
      std::sort(scratch.raw.begin(), scratch.raw.end(), before);
    auto sorted_raw = [&](std::size_t i) -> const RawContact& { return scratch.raw[i]; };
    if (large)
      chunked_for(
          n, std::clamp<std::size_t>(n / 64, 256, 4096),
          [&](std::size_t b, std::size_t e) { convert(sorted_raw, b, e, scene, out, tally); }, tbb::auto_partitioner());
    else
      convert(sorted_raw, 0, n, scene, out, tally);
  }
  res.stats.vf_contacts += tally.vf.load(std::memory_order_relaxed);
  res.stats.ee_contacts += tally.ee.load(std::memory_order_relaxed);
  res.earliest_toi = std::min(res.earliest_toi, tally.earliest.load(std::memory_order_relaxed));
}

}  // namespace mccd::detail
