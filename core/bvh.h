#pragma once
/// @file The scene BVH: one binary hierarchy over all triangles, built once top-down and
/// refitted bottom-up every step (paper section 4.7).
///
/// Layout: nodes in depth-first order in one array; the left child of inner node i is i + 1,
/// its right child is stored; a node's subtree occupies [i, end). Volumes are a parallel
/// array (structure of arrays) so that the hot traversal touches 8 bytes of topology and one
/// volume per node. Indices are 32-bit.
#include <cstdint>
#include <vector>

#include <mccd/core/executor.h>
#include <mccd/core/options.h>
#include <mccd/geometry/mesh.h>

namespace mccd {

/// What the builder needs of a triangle: its box and its centroid.
struct TriangleBounds {
  Vec3 lo, hi, centroid;
};
std::vector<TriangleBounds> triangle_bounds(const std::vector<Triangle>& faces, const Positions& x,
                                            const detail::Executor& ex = detail::serial_executor());

struct BvhNode {
  std::uint32_t end;            ///< 4 bytes: one past the last node of this subtree
  std::uint32_t right_or_leaf;  ///< 4 bytes: right child (inner), or (first << 5 | count - 1) (leaf)
};
static_assert(sizeof(BvhNode) == 8, "BvhNode: two 32-bit fields");

/// The shape of the hierarchy; volumes live beside it, one per node (structure of arrays).
/// A leaf holds 1 to 21 triangles, consecutive in triangle_order().
class BvhTopology {
 public:
  /// The most triangles of a leaf: a leaf's vertices and edges (3 per triangle at most) are
  /// the lanes of 64-bit masks (core/leaf_rule_pairs.h).
  static constexpr unsigned kMaxLeaf = 21;
  /// A leaf's first triangle and count share 32 bits (5 for the count).
  static constexpr std::size_t kMaxTriangles = std::size_t(1) << 27;

  BvhTopology() = default;
  /// Builds top-down over the triangles. Median (the paper's): split the longest axis of the
  /// centroid bounds at its midpoint. Sah: the binned surface area heuristic over the
  /// triangles' boxes, each side's area weighted by the leaves it will at least make (so that
  /// leaves come out full). When every centroid falls on one side, the range is split in half by
  /// count. A range of at most `max_leaf` (1..21) triangles becomes a leaf.
  /// With `mesh_offsets` (triangle ranges of the meshes, [m, m + 1)), every mesh gets its own
  /// subtree, under a top built over the meshes (split at the median of their centroids along
  /// the widest axis); mesh_of_node() then names the mesh below a node (kMixed above nodes of
  /// different meshes).
  /// With `faces` (the triangles' vertex ids, for the SAH build), each connected component of
  /// a mesh that looks like a closed surface (F >= 4 triangles over F / 2 + 2 vertices) gets
  /// its own subtree too, beside the mesh's other triangles, so that self-collision culling can
  /// certify it whole (core/self_culling.h).
  /// Large ranges build their two halves through `ex` (the same tree on any executor).
  BvhTopology(const std::vector<TriangleBounds>& triangles, BvhBuild kind, unsigned max_leaf = 1,
              const std::vector<std::size_t>& mesh_offsets = {}, const std::vector<Triangle>* faces = nullptr,
              const detail::Executor& ex = detail::serial_executor());

  std::size_t size() const { return nodes_.size(); }
  bool leaf(std::uint32_t i) const { return nodes_[i].end == i + 1; }
  std::uint32_t left(std::uint32_t i) const { return i + 1; }
  std::uint32_t right(std::uint32_t i) const { return nodes_[i].right_or_leaf; }
  /// The triangles of leaf i: leaf_count(i) ids from leaf_triangles(i).
  const std::uint32_t* leaf_triangles(std::uint32_t i) const { return order_.data() + (nodes_[i].right_or_leaf >> 5); }
  std::uint32_t leaf_count(std::uint32_t i) const { return (nodes_[i].right_or_leaf & 31u) + 1; }
  /// Where the triangles of leaf i start in triangle_order().
  std::uint32_t leaf_first(std::uint32_t i) const { return nodes_[i].right_or_leaf >> 5; }
  /// Number of nodes in the subtree of i.
  std::uint32_t subtree_size(std::uint32_t i) const { return nodes_[i].end - i; }
  const std::vector<BvhNode>& nodes() const { return nodes_; }
  /// Every triangle once, in leaf order.
  const std::vector<std::uint32_t>& triangle_order() const { return order_; }
  /// Depth of the deepest leaf (the root has depth 0).
  std::uint32_t depth() const { return depth_; }
  unsigned max_leaf() const { return max_leaf_; }
  /// The mesh whose triangles are all below node i, or kMixed (a node of the top).
  static constexpr std::uint32_t kMixed = 0xffffffffu;
  std::uint32_t mesh_of_node(std::uint32_t i) const { return node_mesh_.empty() ? 0 : node_mesh_[i]; }

 private:
  std::vector<BvhNode> nodes_;
  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> node_mesh_;
  std::uint32_t depth_ = 0;
  unsigned max_leaf_ = 1;
};

/// Bottom-up refit of `volumes` (one per node) from `leaf_volume(node)` at the leaves, serially
/// over the node range [begin, end) of one subtree, deepest nodes first. Children are always
/// after their parent in the array, so a reverse sweep sees children before parents.
template <class Volumes, class LeafVolume>
void refit_range(const BvhTopology& bvh, Volumes& volumes, std::uint32_t begin, std::uint32_t end,
                 const LeafVolume& leaf_volume) {
  using BV = typename Volumes::value_type;
  for (std::uint32_t i = end; i-- > begin;)
    volumes[i] = bvh.leaf(i) ? BV(leaf_volume(i)) : BV::merged(volumes[bvh.left(i)], volumes[bvh.right(i)]);
}

}  // namespace mccd
