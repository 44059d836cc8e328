#pragma once
/// @file What a step reports: contacts and the step result.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <mccd/core/stats.h>

namespace mccd {

enum class ContactKind : std::uint8_t { VertexFace = 0, EdgeEdge = 1 };

/// One colliding feature pair. Ids are local to their mesh.
///  VF: `a` is the vertex (of mesh_a), `b` the face (of mesh_b).
///  EE: `a` and `b` are edges (ids as in MeshTopology: sorted by (max, min) vertex);
///      `a_vertices` / `b_vertices` their two vertex ids (min, max). The pair is ordered so
///      that (mesh_a, a) < (mesh_b, b).
struct Contact {
  ContactKind kind;
  std::uint32_t mesh_a, a;
  std::uint32_t mesh_b, b;
  std::array<std::uint32_t, 2> a_vertices{0, 0};  ///< EE only
  std::array<std::uint32_t, 2> b_vertices{0, 0};  ///< EE only
  double toi;  ///< conservative time of impact in [0, 1] (never later than the true one)

  /// The canonical order: kind, then (mesh_a, a), then (mesh_b, b).
  friend bool operator<(const Contact& x, const Contact& y) {
    if (x.kind != y.kind) return x.kind < y.kind;
    if (x.mesh_a != y.mesh_a) return x.mesh_a < y.mesh_a;
    if (x.a != y.a) return x.a < y.a;
    if (x.mesh_b != y.mesh_b) return x.mesh_b < y.mesh_b;
    return x.b < y.b;
  }
  friend bool operator==(const Contact& x, const Contact& y) = default;
};

struct StepResult {
  std::vector<Contact> contacts;  ///< sorted in the canonical order, no duplicates
  /// Earliest time of impact over the contacts; +inf when there is none.
  double earliest_toi = std::numeric_limits<double>::infinity();
  StepStats stats;
};

}  // namespace mccd
