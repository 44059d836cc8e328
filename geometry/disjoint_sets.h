#pragma once
/// @file Internal: disjoint sets over the ids 0..n-1 (union-find with path halving), and the
/// connected components of a triangle mesh's vertices, for the set-up code that groups
/// triangles (the BVH's closed components, the self-culling patches, the generators' pieces).
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

#include <mccd/geometry/topology.h>

namespace mccd::detail {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }

  /// The root of x's set (halving the path on the way).
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  /// Joins a's set to b's: a's root goes under b's.
  void unite(std::uint32_t a, std::uint32_t b) {
    const std::uint32_t rb = find(b);
    parent_[find(a)] = rb;
  }
  /// Every id's root, the sets consumed.
  std::vector<std::uint32_t> roots() && {
    for (std::uint32_t x = 0; x < parent_.size(); ++x) parent_[x] = find(x);
    return std::move(parent_);
  }

 private:
  std::vector<std::uint32_t> parent_;
};

/// Each of the `num_vertices` vertices' connected component over `faces` (vertices joined by
/// the triangles they share), as the id of one vertex of it; a vertex on no triangle is its own.
inline std::vector<std::uint32_t> vertex_components(std::size_t num_vertices, const std::vector<Triangle>& faces) {
  DisjointSets sets(num_vertices);
  for (const Triangle& t : faces)
    for (int k = 1; k < 3; ++k) sets.unite(t[k], t[0]);
  return std::move(sets).roots();
}

}  // namespace mccd::detail
