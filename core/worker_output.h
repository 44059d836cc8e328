#pragma once
/// @file Internal: what one unit of work (a block of the front, a task of a traversal, a serial
/// pass) produces: its part of the next front, its contacts, its counters. Each unit writes
/// only its own output; outputs are joined after the parallel loop, in unit order, so the
/// result does not depend on scheduling.
#include <cstdint>
#include <vector>

#include <mccd/core/contact.h>

namespace mccd::detail {

/// A BVTT pair node: two BVH node ids, a < b (a == b is a self node).
struct NodePair {
  std::uint32_t a, b;  ///< 8 bytes
  friend bool operator<(const NodePair& x, const NodePair& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; }
  friend bool operator==(const NodePair& x, const NodePair& y) = default;
};
static_assert(sizeof(NodePair) == 8);

/// A contact as found, with global ids (VF: vertex, face; EE: edge a < edge b).
struct RawContact {
  std::uint32_t a, b;
  ContactKind kind;
  double toi;
};

struct WorkerOutput {
  std::vector<NodePair> front;       ///< the front nodes this unit keeps or sprouts
  std::vector<RawContact> contacts;  ///< found by this unit, not yet handed to the buffer
  std::vector<NodePair> stack;       ///< traversal stack (kept to reuse the allocation)
  StepStats stats;                   ///< this unit's counts
  void clear() {
    front.clear();
    contacts.clear();
    stack.clear();
    stats = {};
  }
};

}  // namespace mccd::detail
