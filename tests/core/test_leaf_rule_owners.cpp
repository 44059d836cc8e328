// The leaf rule's ownership (core/leaf_rule_owners.h): every vertex and edge has exactly one owner
// leaf, which holds a triangle around it, and each leaf's owned vertices plus its foreign
// corners are exactly its triangles' corners, each once (what the stepper's leaf refit merges).
#include <mccd/core/bvh.h>
#include <mccd/core/leaf_rule_owners.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "fixtures/shapes.h"

using namespace mccd;
using namespace mccd::detail;

namespace {
void check_ownership(const TriMesh& m, BvhBuild build, unsigned leaf_size) {
  MeshTopology topo(m.num_vertices(), m.faces);
  BvhTopology bvh(triangle_bounds(m.faces, m.vertices), build, leaf_size);
  LeafOwnership owners(bvh, topo);
  const VolumeLayout& layout = owners.layout();
  std::vector<int> owned_times(topo.num_vertices(), 0);
  std::size_t leaves = 0;
  for (std::uint32_t n = 0; n < bvh.size(); ++n) {
    if (!bvh.leaf(n)) {
      EXPECT_EQ(owners.vertex_begin(n), owners.vertex_begin(n + 1)) << "inner node " << n << " owns vertices";
      EXPECT_EQ(owners.foreign_begin(n), owners.foreign_begin(n + 1)) << "inner node " << n << " has corners";
      continue;
    }
    ++leaves;
    std::set<std::uint32_t> corners;  // vertex slots of the leaf's triangles' corners
    for (std::uint32_t k = 0; k < bvh.leaf_count(n); ++k)
      for (std::uint32_t v : topo.faces()[bvh.leaf_triangles(n)[k]]) corners.insert(layout.vertex_slot[v]);
    std::multiset<std::uint32_t> listed;
    for (std::uint32_t s = owners.vertex_begin(n); s != owners.vertex_begin(n + 1); ++s) {
      listed.insert(s);
      ++owned_times[owners.vertex(s)];
      EXPECT_EQ(layout.vertex_slot[owners.vertex(s)], s);
    }
    for (std::uint32_t i = owners.foreign_begin(n); i != owners.foreign_begin(n + 1); ++i) {
      const std::uint32_t s = owners.foreign_corner(i);
      EXPECT_TRUE(s < owners.vertex_begin(n) || s >= owners.vertex_begin(n + 1)) << "leaf " << n << " slot " << s;
      listed.insert(s);
    }
    EXPECT_EQ(listed.size(), corners.size()) << "leaf " << n << ": a corner listed twice or missing";
    EXPECT_TRUE(std::equal(corners.begin(), corners.end(), listed.begin(), listed.end())) << "leaf " << n;
  }
  EXPECT_GT(leaves, 1u);
  for (std::uint32_t v = 0; v < topo.num_vertices(); ++v)
    EXPECT_EQ(owned_times[v], topo.vertex_face_count(v) ? 1 : 0) << "vertex " << v;
}
}  // namespace

TEST(LeafOwnership, OwnedAndForeignCornersCoverEachLeafOnce) {
  check_ownership(make_grid_mesh(12), BvhBuild::Sah, 8);
  check_ownership(make_grid_mesh(9), BvhBuild::Median, 1);
  check_ownership(make_sphere_mesh(8, 12), BvhBuild::Sah, 5);
}

namespace {
// Each leaf's apart masks name exactly its own non-adjacent pairs: an edge against the later
// edges of the leaf that share no end with it, a vertex against the leaf's faces that do not
// have it as a corner (checked against the ids, pair by pair).
void check_apart_masks(const TriMesh& m, unsigned leaf_size) {
  MeshTopology topo(m.num_vertices(), m.faces);
  BvhTopology bvh(triangle_bounds(m.faces, m.vertices), BvhBuild::Sah, leaf_size);
  LeafOwnership owners(bvh, topo);
  std::size_t apart_pairs = 0, adjacent_pairs = 0;
  for (std::uint32_t n = 0; n < bvh.size(); ++n) {
    if (!bvh.leaf(n)) continue;
    const std::uint32_t eb = owners.edge_begin(n), ee = owners.edge_begin(n + 1);
    for (std::uint32_t x = eb; x != ee; ++x) {
      const Edge& a = topo.edges()[owners.edge(x)];
      for (std::uint32_t y = eb; y != ee; ++y) {
        const Edge& b = topo.edges()[owners.edge(y)];
        const bool shared = a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1];
        const bool bit = owners.apart_edges(x) >> (y - eb) & 1u;
        EXPECT_EQ(bit, y > x && !shared) << "leaf " << n << " edges " << owners.edge(x) << ", " << owners.edge(y);
        (shared ? adjacent_pairs : apart_pairs) += y > x;
      }
      EXPECT_EQ(owners.apart_edges(x) >> (ee - eb), 0u) << "leaf " << n << ": bits past its edges";
    }
    for (std::uint32_t s = owners.vertex_begin(n); s != owners.vertex_begin(n + 1); ++s) {
      const std::uint32_t v = owners.vertex(s);
      for (std::uint32_t k = 0; k < bvh.leaf_count(n); ++k) {
        const Triangle& t = topo.faces()[bvh.leaf_triangles(n)[k]];
        const bool corner = t[0] == v || t[1] == v || t[2] == v;
        EXPECT_EQ(bool(owners.apart_faces(s) >> k & 1u), !corner) << "leaf " << n << " vertex " << v << " face " << k;
      }
      EXPECT_EQ(owners.apart_faces(s) >> bvh.leaf_count(n), 0u) << "leaf " << n << ": bits past its faces";
    }
  }
  // Both kinds occur in leaves of several triangles, so the masks are not trivially all set or
  // all clear; a one-triangle leaf's edges all share ends.
  if (leaf_size > 1)
    EXPECT_GT(apart_pairs, 0u);
  else
    EXPECT_EQ(apart_pairs, 0u);
  EXPECT_GT(adjacent_pairs, 0u);
}
}  // namespace

TEST(LeafOwnership, ApartMasksNameEachLeafsNonAdjacentPairs) {
  check_apart_masks(make_grid_mesh(12), 16);
  check_apart_masks(make_sphere_mesh(8, 12), 7);
  check_apart_masks(make_grid_mesh(7), 1);
}

// The end filter may pass an edge that shares no end with a leaf's edges (a hash collision),
// but never fails one that shares an end: find() skips its exact test only where it fails.
TEST(LeafOwnership, EndFilterPassesEveryEdgeSharingAnEnd) {
  for (const TriMesh& m : {make_grid_mesh(12), make_sphere_mesh(8, 12)}) {
    MeshTopology topo(m.num_vertices(), m.faces);
    BvhTopology bvh(triangle_bounds(m.faces, m.vertices), BvhBuild::Sah, 8);
    LeafOwnership owners(bvh, topo);
    const std::size_t edges = topo.num_edges();
    std::size_t sharing = 0, failed = 0;
    for (std::uint32_t n = 0; n < bvh.size(); ++n) {
      if (!bvh.leaf(n)) continue;
      const LeafOwnership::EndFilter& filter = owners.end_filter(n);
      for (std::uint32_t s = 0; s < edges; ++s) {
        bool shares = false;
        for (std::uint32_t t = owners.edge_begin(n); t != owners.edge_begin(n + 1); ++t)
          shares |= shares_end(owners.edge_ends(s), owners.edge_ends(t));
        const bool passes = LeafOwnership::may_share_end(filter, owners.edge_ends(s));
        if (shares) {
          ++sharing;
          EXPECT_TRUE(passes) << "leaf " << n << ", edge slot " << s;
        }
        failed += !passes;
      }
    }
    EXPECT_GT(sharing, 0u);
    EXPECT_GT(failed, 0u) << "the filter skips nothing";
  }
}

// The arrays the leaf pairs read through held pointers (edges_from, edge_ends_from,
// face_corners_from) are the per-slot tables: every leaf's entries, and the mesh's own edges and
// face corners behind them; from the end slot on, nothing (the pointer one past the last).
TEST(LeafOwnership, ArraysFromASlotAreThePerSlotTables) {
  const TriMesh m = make_sphere_mesh(8, 12);
  MeshTopology topo(m.num_vertices(), m.faces);
  BvhTopology bvh(triangle_bounds(m.faces, m.vertices), BvhBuild::Sah, 8);
  LeafOwnership owners(bvh, topo);
  std::size_t leaves = 0;
  for (std::uint32_t n = 0; n < bvh.size(); ++n) {
    if (!bvh.leaf(n)) continue;
    ++leaves;
    const std::uint32_t eb = owners.edge_begin(n), ne = owners.edge_begin(n + 1) - eb;
    const std::uint32_t* ids = owners.edges_from(eb);
    const Edge* ends = owners.edge_ends_from(eb);
    for (std::uint32_t j = 0; j < ne; ++j) {
      EXPECT_EQ(ids[j], owners.edge(eb + j)) << "leaf " << n << " edge lane " << j;
      EXPECT_EQ(ends[j], topo.edges()[ids[j]]) << "leaf " << n << " edge lane " << j;
    }
    const Triangle* corners = owners.face_corners_from(bvh.leaf_first(n));
    for (std::uint32_t k = 0; k < bvh.leaf_count(n); ++k)
      EXPECT_EQ(corners[k], topo.faces()[bvh.leaf_triangles(n)[k]]) << "leaf " << n << " face " << k;
  }
  EXPECT_GT(leaves, 1u);
  const auto last_edge = static_cast<std::uint32_t>(topo.num_edges());
  EXPECT_EQ(owners.edges_from(last_edge), owners.edges_from(0) + last_edge);
  EXPECT_EQ(owners.edge_ends_from(last_edge), owners.edge_ends_from(0) + last_edge);
}
