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

#include <mccd/geometry/mesh.h>

namespace mccd {

struct BvhNode {
  std::uint32_t end;           ///< 4 bytes: one past the last node of this subtree
  std::uint32_t right_or_tri;  ///< 4 bytes: right child (inner) or triangle id (leaf)
};
static_assert(sizeof(BvhNode) == 8, "BvhNode: two 32-bit fields");

/// The shape of the hierarchy; volumes live beside it (see Bvh below).
class BvhTopology {
 public:
  BvhTopology() = default;
  /// Builds over triangles with the given centroids: split the longest axis of the centroid
  /// bounds at its midpoint (spatial median); when every centroid falls on one side, split
  /// the index range in half instead. One triangle per leaf.
  explicit BvhTopology(const std::vector<Vec3>& centroids);

  std::size_t size() const { return nodes_.size(); }
  bool leaf(std::uint32_t i) const { return nodes_[i].end == i + 1; }
  std::uint32_t left(std::uint32_t i) const { return i + 1; }
  std::uint32_t right(std::uint32_t i) const { return nodes_[i].right_or_tri; }
  std::uint32_t triangle(std::uint32_t i) const { return nodes_[i].right_or_tri; }
  /// Number of nodes in the subtree of i (2 * leaves - 1).
  std::uint32_t subtree_size(std::uint32_t i) const { return nodes_[i].end - i; }
  /// The leaf node holding triangle t.
  std::uint32_t leaf_of(std::uint32_t t) const { return leaf_of_[t]; }
  const std::vector<BvhNode>& nodes() const { return nodes_; }
  /// Depth of the deepest leaf (the root has depth 0).
  std::uint32_t depth() const { return depth_; }

 private:
  std::vector<BvhNode> nodes_;
  std::vector<std::uint32_t> leaf_of_;
  std::uint32_t depth_ = 0;
};

/// Bottom-up refit of `volumes` (one per node) from `leaf_volume(triangle)`, serially over
/// the node range [begin, end) of one subtree, deepest nodes first. Children are always
/// after their parent in the array, so a reverse sweep sees children before parents.
template <class BV, class LeafVolume>
void refit_range(const BvhTopology& bvh, std::vector<BV>& volumes, std::uint32_t begin, std::uint32_t end,
                 const LeafVolume& leaf_volume) {
  for (std::uint32_t i = end; i-- > begin;) {
    if (bvh.leaf(i))
      volumes[i] = leaf_volume(bvh.triangle(i));
    else
      volumes[i] = BV::merged(volumes[bvh.left(i)], volumes[bvh.right(i)]);
  }
}

}  // namespace mccd
