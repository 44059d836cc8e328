#pragma once
/// @file How a scene steps: the method, the bounding volume, the front's rebuild rule, the
/// minimum distance, and where the parallel stages run.
#include <cstdint>
#include <vector>

#include <oneapi/tbb/task_arena.h>

namespace mccd {

/// How a step finds its candidate pairs. All four return identical contacts.
enum class Method : std::uint8_t {
  BruteForce,  ///< every feature pair, swept-box sweep and prune; the oracle, small scenes
  Traverse,    ///< BVTT traversal from the root every step, serial (the paper's serial baseline)
  Phc,         ///< the paper's PHC baseline (section 3.3): from the root every step, the BVTT's
               ///< top expanded breadth-first into subtasks that then run in parallel
  Fbd,         ///< front-based decomposition (the paper's FBD, the default): the BVTT front
               ///< tracked from step to step in parallel blocks, adaptive rebuild
};
/// "bruteforce", "traverse", "phc" or "fbd".
const char* to_string(Method m);
/// Parses "bruteforce", "traverse", "phc", "fbd" (or its alias "front"); throws mccd::Error
/// naming the accepted values otherwise.
Method parse_method(const char* name);

/// How the scene BVH is built (once, on the meshes' initial positions).
enum class BvhBuild : std::uint8_t {
  Median,  ///< the paper's: longest axis of the centroid bounds, split at its midpoint
  Sah,     ///< binned surface area heuristic over the triangles' boxes (fewer volume tests)
};
/// "median" or "sah".
const char* to_string(BvhBuild b);
/// Parses "median" or "sah"; throws mccd::Error otherwise.
BvhBuild parse_bvh_build(const char* name);

/// Where each vertex-face and edge-edge pair is tested: at exactly one place per step, so
/// every choice reports identical contacts; they differ in cost and in what the front holds.
enum class Representatives : std::uint8_t {
  Default,    ///< Leaf with the SAH tree, Canonical with the median tree (the paper's setting)
  Leaf,       ///< every vertex and edge is owned by the BVH leaf of its first triangle; a pair is
              ///< tested at the leaf pair of its owners (adjacent leaves included) or inside one
              ///< leaf; no search and no orphan set (core/leaf_rule_owners.h)
  Canonical,  ///< the paper's (section 4.6): the first non-adjacent triangle pair around the two
              ///< features carries the pair; pairs with no such carrier form the orphan set,
              ///< tested every step, and leaf pairs of adjacent triangles never enter the front
};
/// "default", "leaf" or "canonical".
const char* to_string(Representatives r);
/// Parses "default", "leaf" or "canonical"; throws mccd::Error otherwise.
Representatives parse_representatives(const char* name);
struct SceneOptions;
/// The rule a scene with these options uses (Default resolved by the BVH build).
Representatives resolved_representatives(const SceneOptions& options);

/// The bounding volume of the scene BVH.
enum class VolumeKind : std::uint8_t { Kdop18, Aabb };
/// "kdop18" or "aabb".
const char* to_string(VolumeKind v);
/// Parses "kdop18" or "aabb"; throws mccd::Error otherwise.
VolumeKind parse_volume(const char* name);

/// When a feature pair's own quarter volumes are tested under the leaf rule, relative to the
/// coplanarity filter (core/feature_tests.h). The filter decides each quarter of the step on
/// its own, so every order gives the same contacts, times and elementary tests; only the work
/// differs (and StepStats::vf_filtered / ee_filtered: after the filter, they also count pairs
/// whose volumes would not have met).
enum class VolumeOrder : std::uint8_t {
  Adaptive,     ///< after the filter at leaves that move little against their edges' lengths
                ///< (where nearly every pair's volumes meet), first elsewhere
  First,        ///< always first: the filter sees only pairs whose volumes meet
  AfterFilter,  ///< always after the filter, only for the pairs it keeps
};
/// "adaptive", "first" or "after-filter".
const char* to_string(VolumeOrder o);
/// Parses "adaptive", "first" or "after-filter"; throws mccd::Error otherwise.
VolumeOrder parse_volume_order(const char* name);

/// How one mesh takes part in the scene.
struct MeshOptions {
  /// A static mesh keeps its initial positions: a step needs none for it (an empty
  /// PositionsView, or its unchanged positions, checked), it is never tested against itself
  /// nor against another static mesh, and its part of the BVH is never refitted.
  bool is_static = false;
  /// Whether the mesh's own triangles are tested against each other (off for a rigid or
  /// kinematic body, whose triangles cannot collide with each other). Off for static meshes.
  bool self_collision = true;
};

struct SceneOptions {
  Method method = Method::Fbd;  ///< default method of step() and advance()
  VolumeKind volume = VolumeKind::Kdop18;
  BvhBuild bvh = BvhBuild::Sah;
  /// Triangles per BVH leaf, 1 to 21; 0 picks the build's default (1 for median, as the
  /// paper; 21, the most, for sah).
  unsigned leaf_size = 0;
  /// Where each feature pair is tested (Default: Leaf with sah, Canonical with median).
  Representatives representatives = Representatives::Default;
  /// Rebuild the front from the root when S/L (nodes inserted by sprouting since the last
  /// build over the front size) exceeds this (paper equation 3). > 0.
  double rebuild_sprout_ratio = 0.30;
  /// ... or when B/L (nodes invalidated since the last build) exceeds this (equation 4). > 0.
  double rebuild_invalid_ratio = 0.45;
  /// Cap on the bytes the front keeps between fbd steps (0: no cap). A front that would hold
  /// more after a step is dropped instead of kept (and its buffers released), so the next step
  /// rebuilds it from the root rather than growing it. Contacts never depend on the cap; only
  /// the work of the next step does (StepStats::front_size is 0 after a dropped front).
  std::size_t max_front_bytes = 0;
  /// One entry per mesh, or empty: every mesh deforming, with self-collision.
  std::vector<MeshOptions> meshes;
  /// Report pairs that come within this distance (finite, >= 0) as contacts.
  double min_distance = 0.0;
  /// Skip the pairs inside patches of a mesh certified, each step, to be unable to touch
  /// themselves (a disk whose triangles keep their orientation seen along one axis and whose
  /// boundary, seen along it, stays a simple curve; core/self_culling.h). Exact: contacts do
  /// not change. Used only under the leaf rule and without a minimum distance.
  bool self_culling = true;
  /// When feature pairs' quarter volumes are tested, relative to the coplanarity filter (leaf
  /// rule, no minimum distance; VolumeOrder). Same contacts in every order.
  VolumeOrder volume_order = VolumeOrder::Adaptive;
  /// Where the parallel stages run; nullptr: the caller's arena. mccd never creates a
  /// global_control and never changes the arena's concurrency.
  tbb::task_arena* arena = nullptr;
  /// Run a step's stages through its flow graph (parallel/step_graph.h; the pairs no front
  /// node holds beside the search), or, when false, call them one after the other on the
  /// calling thread (each stage still parallel inside). Scenes of fewer than 8,192 triangles
  /// call them in sequence either way: a step there is a fraction of a millisecond, and waking
  /// a second thread for the other branch costs more than it saves. Same results either way;
  /// false exists to measure what the graph costs.
  bool flow_graph = true;
  /// Measure each stage's work and span (StepStats::ws_*): every task of the stages' parallel
  /// loops is timed (a clock read per task). For the benchmarks' scaling model; results do
  /// not change.
  bool work_span = false;
};

/// Throws mccd::Error naming the option when a value is out of range (an unknown method or
/// volume, a ratio <= 0 or NaN, a negative or non-finite distance). The count of mesh options
/// is checked by the scene.
void validate(const SceneOptions& options);

}  // namespace mccd
