#include <mccd/geometry/topology.h>

#include <algorithm>

#include <mccd/geometry/large_allocator.h>

namespace mccd {

MeshTopology::MeshTopology(std::size_t num_vertices, const std::vector<Triangle>& faces) : faces_(faces) {
  const std::size_t nf = faces.size();
  // vertex -> faces, CSR
  // Every array below is written in full right away: its pages backed in one call each
  // (reserve_backed) rather than faulted in one by one.
  detail::backed_assign(vertex_face_offsets_, num_vertices + 1);
  for (const Triangle& t : faces)
    for (auto v : t) ++vertex_face_offsets_[v + 1];
  for (std::size_t v = 0; v < num_vertices; ++v) vertex_face_offsets_[v + 1] += vertex_face_offsets_[v];
  detail::backed_assign(vertex_faces_, vertex_face_offsets_.back());
  {
    std::vector<std::uint32_t> fill;
    detail::reserve_backed(fill, num_vertices);
    fill.assign(vertex_face_offsets_.begin(), vertex_face_offsets_.end() - 1);
    for (std::size_t f = 0; f < nf; ++f)
      for (auto v : faces[f]) vertex_faces_[fill[v]++] = static_cast<std::uint32_t>(f);
  }
  // half-edges keyed by (max, min), then unique: gives the libigl order.
  struct HalfEdge {
    std::uint32_t hi, lo, face, corner;
  };
  // Sorted by (hi, lo, face) in linear time: bucketed by hi (a counting sort), then each
  // bucket, a few half-edges around one vertex, sorted by (lo, face).
  detail::LargeVector<HalfEdge> half(3 * nf);  // megabytes, touched once: huge pages (large_allocator.h)
  {
    std::vector<std::uint32_t> start;
    detail::backed_assign(start, num_vertices + 1);
    for (const Triangle& t : faces)
      for (std::uint32_t k = 0; k < 3; ++k) ++start[std::max(t[k], t[(k + 1) % 3]) + 1];
    for (std::size_t v = 0; v < num_vertices; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> at;
    detail::reserve_backed(at, num_vertices);
    at.assign(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f < nf; ++f)
      for (std::uint32_t k = 0; k < 3; ++k) {
        const std::uint32_t a = faces[f][k], b = faces[f][(k + 1) % 3];
        half[at[std::max(a, b)]++] = {std::max(a, b), std::min(a, b), static_cast<std::uint32_t>(f), k};
      }
    auto before = [](const HalfEdge& x, const HalfEdge& y) { return x.lo != y.lo ? x.lo < y.lo : x.face < y.face; };
    for (std::size_t v = 0; v < num_vertices; ++v)
      std::sort(half.begin() + start[v], half.begin() + start[v + 1], before);
  }
  // Half-edges of one edge are adjacent after the sort, ordered by face: the CSR of edge
  // faces falls out directly.
  detail::backed_assign(face_edges_, nf, {0, 0, 0});
  detail::reserve_backed(edge_faces_, half.size());
  // At most one edge per half-edge: reserved once instead of grown (each growth copies and
  // touches new pages; the unused part of the reservation is never touched). Half as many
  // edges as half-edges where every edge has two faces: that many backed at once.
  edges_.reserve(half.size());
  edge_face_offsets_.reserve(half.size() + 1);
  detail::populate_pages(edges_.data(), half.size() / 2 * sizeof(Edge));
  detail::populate_pages(edge_face_offsets_.data(), half.size() / 2 * sizeof(std::uint32_t));
  for (std::size_t i = 0; i < half.size(); ++i) {
    if (i == 0 || half[i].hi != half[i - 1].hi || half[i].lo != half[i - 1].lo) {
      edges_.push_back({half[i].lo, half[i].hi});
      edge_face_offsets_.push_back(static_cast<std::uint32_t>(i));
    }
    const auto e = static_cast<std::uint32_t>(edges_.size() - 1);
    edge_faces_.push_back(half[i].face);
    face_edges_[half[i].face][half[i].corner] = e;
  }
  edge_face_offsets_.push_back(static_cast<std::uint32_t>(half.size()));
}

std::size_t MeshTopology::num_boundary_edges() const {
  std::size_t n = 0;
  for (std::size_t e = 0; e < edges_.size(); ++e) n += edge_face_count(e) == 1;
  return n;
}

std::size_t MeshTopology::num_nonmanifold_edges() const {
  std::size_t n = 0;
  for (std::size_t e = 0; e < edges_.size(); ++e) n += edge_face_count(e) > 2;
  return n;
}

std::int64_t MeshTopology::find_edge(std::uint32_t a, std::uint32_t b) const {
  const Edge key{std::min(a, b), std::max(a, b)};
  auto it = std::lower_bound(edges_.begin(), edges_.end(), key, [](const Edge& x, const Edge& y) {
    return x[1] != y[1] ? x[1] < y[1] : x[0] < y[0];
  });
  if (it == edges_.end() || *it != key) return -1;
  return it - edges_.begin();
}

}  // namespace mccd
