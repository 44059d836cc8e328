#pragma once
/// @file What a step reports: contacts, statistics, and the step result.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace mccd {

/// How a step finds its candidate pairs. All three return identical contacts.
enum class Method : std::uint8_t {
  BruteForce,  ///< every feature pair, swept-box sweep and prune; the oracle, small scenes
  Traverse,    ///< BVTT traversal from the root every step (the paper's serial baseline)
  Front,       ///< BVTT front tracking with adaptive rebuild (the paper's FBD)
};
const char* to_string(Method m);
/// Parses "bruteforce", "traverse" or "front"; throws mccd::Error otherwise.
Method parse_method(const char* name);

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

/// What a step did. Counts are exact; times are wall-clock seconds.
struct StepStats {
  Method method = Method::Front;
  std::uint64_t volume_tests = 0;      ///< bounding-volume overlap tests of BVH node pairs
  std::uint64_t feature_box_tests = 0; ///< feature-pair swept-volume tests before elementary tests
  std::uint64_t vf_tests = 0;          ///< vertex-face elementary tests run
  std::uint64_t ee_tests = 0;          ///< edge-edge elementary tests run
  /// Elementary tests that passed their own cheap filters (swept box, Bernstein coplanarity)
  /// and reached root isolation and the inside test.
  std::uint64_t vf_root_tests = 0;
  std::uint64_t ee_root_tests = 0;
  std::uint64_t vf_contacts = 0;
  std::uint64_t ee_contacts = 0;
  std::uint64_t leaf_pairs = 0;        ///< non-adjacent leaf pairs whose volumes overlapped
  /// Adjacent leaf pairs the traversal reached and skipped (their features are the orphan
  /// set's); without the orphan set they would be front nodes (paper equation 5, B_a).
  std::uint64_t adjacent_leaf_pairs = 0;
  std::uint64_t front_size = 0;        ///< front nodes after the step (Front only)
  std::uint64_t sprouted = 0;          ///< nodes inserted by sprouting this step (S)
  std::uint64_t invalidated = 0;       ///< front nodes that overlapped and were expanded (B)
  std::uint64_t rebuilds = 0;          ///< 1 when the front was built from the root this step
  std::uint64_t orphan_vf_tested = 0;  ///< orphan VF pairs whose boxes overlapped and were tested
  std::uint64_t orphan_ee_tested = 0;
  std::uint64_t front_bytes = 0;       ///< bytes held by the front buffers
  double t_update = 0, t_refit = 0, t_front = 0, t_orphans = 0, t_total = 0;
};

struct StepResult {
  std::vector<Contact> contacts;  ///< sorted in the canonical order, no duplicates
  /// Earliest time of impact over the contacts; +inf when there is none.
  double earliest_toi = std::numeric_limits<double>::infinity();
  StepStats stats;
};

}  // namespace mccd
