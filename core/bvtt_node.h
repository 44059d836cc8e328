#pragma once
/// @file Internal: the node of the bounding volume test tree (core/bvtt.h), the unit of the
/// front (core/front.h) and of every traversal stack.
#include <cstdint>

namespace mccd::detail {

/// A BVTT pair node: two BVH node ids, a < b (a == b is a self node).
struct NodePair {
  std::uint32_t a, b;  ///< 8 bytes
  friend bool operator<(const NodePair& x, const NodePair& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; }
  friend bool operator==(const NodePair& x, const NodePair& y) = default;
};
static_assert(sizeof(NodePair) == 8);

}  // namespace mccd::detail
