#include <mccd/core/leaf_rule_owners.h>

#include <algorithm>

#include <mccd/geometry/large_allocator.h>

namespace mccd::detail {

LeafOwnership::LeafOwnership(const BvhTopology& bvh, const MeshTopology& topo, const Executor& ex) {
  // Every array here is written in full right away: its pages backed in one call each
  // (backed_assign) rather than faulted in one by one.
  std::vector<std::uint32_t> leaf_of_face;
  backed_assign(leaf_of_face, topo.num_faces());
  for (std::uint32_t i = 0; i < bvh.size(); ++i)
    if (bvh.leaf(i))
      for (std::uint32_t k = 0; k < bvh.leaf_count(i); ++k) leaf_of_face[bvh.leaf_triangles(i)[k]] = i;
  // Counting sort of the owned features by owner node, ascending ids within a node.
  auto bucket = [&](std::size_t n, auto first_face, std::vector<std::uint32_t>& begin, std::vector<std::uint32_t>& ids) {
    begin.assign(bvh.size() + 1, 0);
    for (std::size_t x = 0; x < n; ++x)
      if (first_face(x) != kNoFace) ++begin[leaf_of_face[first_face(x)] + 1];
    for (std::size_t i = 1; i < begin.size(); ++i) begin[i] += begin[i - 1];
    backed_assign(ids, begin.back());
    std::vector<std::uint32_t> at(begin.begin(), begin.end() - 1);
    for (std::size_t x = 0; x < n; ++x)
      if (first_face(x) != kNoFace) ids[at[leaf_of_face[first_face(x)]]++] = static_cast<std::uint32_t>(x);
  };
  bucket(
      topo.num_vertices(),
      [&](std::size_t v) { return topo.vertex_face_count(v) ? *topo.vertex_faces_begin(v) : kNoFace; },
      vertex_begin_, vertices_);
  bucket(
      topo.num_edges(), [&](std::size_t e) { return *topo.edge_faces_begin(e); }, edge_begin_, edges_);

  // The storage layout: vertices and edges by owner (isolated vertices last), faces in the
  // BVH's triangle order.
  VolumeLayout& l = layout_;
  backed_assign(l.vertex_slot, topo.num_vertices(), kNoFace);
  for (std::size_t s = 0; s < vertices_.size(); ++s) l.vertex_slot[vertices_[s]] = static_cast<std::uint32_t>(s);
  auto next = static_cast<std::uint32_t>(vertices_.size());
  for (std::uint32_t& s : l.vertex_slot)
    if (s == kNoFace) s = next++;  // isolated vertices: stored, never tested
  // Permutations and copies in slot order: every entry written once, in parallel blocks
  // (megabytes for a large scene).
  auto blocks = [&ex](std::size_t n, const auto& body) { ex.static_for(n, 16384, body); };
  // Loops over the BVH's nodes: far fewer items than a chunk of the loops above, each leaf's
  // work growing with the square of its features; small chunks, dealt out as threads free up.
  auto node_blocks = [&ex](std::size_t n, const auto& body) { ex.dynamic_for(n, 128, body); };
  backed_assign(l.edge_slot, topo.num_edges());
  backed_assign(edge_ends_, topo.num_edges());
  blocks(edges_.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t s = b; s != e; ++s) {
      l.edge_slot[edges_[s]] = static_cast<std::uint32_t>(s);
      edge_ends_[s] = topo.edges()[edges_[s]];
    }
  });
  const std::vector<std::uint32_t>& order = bvh.triangle_order();
  backed_assign(l.face_slot, topo.num_faces());
  backed_assign(face_corners_, order.size());
  backed_assign(face_corner_slots_, order.size());
  blocks(order.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t s = b; s != e; ++s) {
      l.face_slot[order[s]] = static_cast<std::uint32_t>(s);
      face_corners_[s] = topo.faces()[order[s]];
      for (int k = 0; k < 3; ++k) face_corner_slots_[s][k] = l.vertex_slot[face_corners_[s][k]];
    }
  });
  // The apart masks of each leaf's own features (LeafOwnership::apart_edges, apart_faces).
  backed_assign(apart_edges_, edges_.size());
  backed_assign(apart_faces_, vertices_.size());
  node_blocks(bvh.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i != e; ++i) {
      const auto node = static_cast<std::uint32_t>(i);
      if (!bvh.leaf(node)) continue;
      for (std::uint32_t x = edge_begin_[i]; x != edge_begin_[i + 1]; ++x) {
        std::uint64_t apart = 0;
        const Edge& ex = edge_ends_[x];
        for (std::uint32_t y = x + 1; y != edge_begin_[i + 1]; ++y)
          if (!shares_end(ex, edge_ends_[y])) apart |= std::uint64_t(1) << (y - edge_begin_[i]);
        apart_edges_[x] = apart;
      }
      for (std::uint32_t x = vertex_begin_[i]; x != vertex_begin_[i + 1]; ++x) {
        std::uint32_t apart = 0;
        for (std::uint32_t k = 0; k < bvh.leaf_count(node); ++k) {
          if (!has_corner(face_corners_[bvh.leaf_first(node) + k], vertices_[x])) apart |= 1u << k;
        }
        apart_faces_[x] = apart;
      }
    }
  });
  // Each leaf's corners that it does not own, once each: counted, then written, in parallel
  // blocks of nodes (two passes: a scratch array would cost more in fresh pages than the
  // second pass does).
  auto foreign_of = [&](std::size_t i, std::uint32_t (&out)[3 * BvhTopology::kMaxLeaf]) {
    unsigned n = 0;
    const auto node = static_cast<std::uint32_t>(i);
    if (!bvh.leaf(node)) return n;
    for (std::uint32_t s = bvh.leaf_first(node); s != bvh.leaf_first(node) + bvh.leaf_count(node); ++s)
      for (std::uint32_t c : face_corner_slots_[s])
        if ((c < vertex_begin_[i] || c >= vertex_begin_[i + 1]) && std::find(out, out + n, c) == out + n) out[n++] = c;
    return n;
  };
  end_filters_.assign(bvh.size(), EndFilter{});
  node_blocks(bvh.size(), [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i != e; ++i)
      for (std::uint32_t s = edge_begin_[i]; s != edge_begin_[i + 1]; ++s)
        for (std::uint32_t v : edge_ends_[s]) {
          const unsigned h = end_hash(v);
          end_filters_[i].bits[h >> 6] |= std::uint64_t(1) << (h & 63);
        }
  });
  foreign_begin_.assign(bvh.size() + 1, 0);
  node_blocks(bvh.size(), [&](std::size_t b, std::size_t e) {
    std::uint32_t buf[3 * BvhTopology::kMaxLeaf];
    for (std::size_t i = b; i != e; ++i) foreign_begin_[i + 1] = foreign_of(i, buf);
  });
  for (std::size_t i = 1; i < foreign_begin_.size(); ++i) foreign_begin_[i] += foreign_begin_[i - 1];
  backed_assign(foreign_, foreign_begin_.back());
  node_blocks(bvh.size(), [&](std::size_t b, std::size_t e) {
    std::uint32_t buf[3 * BvhTopology::kMaxLeaf];
    for (std::size_t i = b; i != e; ++i) std::copy(buf, buf + foreign_of(i, buf), foreign_.begin() + foreign_begin_[i]);
  });
}

}  // namespace mccd::detail
