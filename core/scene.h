#pragma once
/// @file The public API: a scene of deforming triangle meshes, stepped over time.
///
///   mccd::Scene scene({cloth, body});                 // built once
///   auto r = scene.step({cloth_t0, body_t0}, {cloth_t1, body_t1});
///   for (const mccd::Contact& c : r.contacts) ...     // sorted, earliest toi in r.earliest_toi
///   r = scene.advance({cloth_t2, body_t2});           // t1 -> t2
///
/// Thread safety: one step at a time per scene; different scenes are independent.
#include <memory>
#include <optional>
#include <vector>

#include <oneapi/tbb/task_arena.h>

#include "core/contact.h"
#include "geometry/mesh.h"


namespace mccd {

/// The bounding volume of the scene BVH.
enum class VolumeKind : std::uint8_t { Kdop18, Aabb };

struct SceneOptions {
  Method method = Method::Front;        ///< default method of step() and advance()
  VolumeKind volume = VolumeKind::Kdop18;
  /// Rebuild the front from the root when S/L (nodes inserted by sprouting since the last
  /// build over the front size) exceeds this (paper equation 3).
  double rebuild_sprout_ratio = 0.30;
  /// ... or when B/L (nodes invalidated since the last build) exceeds this (equation 4).
  double rebuild_invalid_ratio = 0.45;
  /// Report pairs that come within this distance (>= 0) as contacts.
  double min_distance = 0.0;
  /// Where the parallel stages run; nullptr: the caller's arena.
  tbb::task_arena* arena = nullptr;
};

/// A view of one mesh's positions: row i is vertex i (x, y, z), row-major doubles. Read during
/// the call only.
using PositionsView = Eigen::Ref<const Positions>;

class Scene {
 public:
  /// Builds the scene from meshes (their positions are the initial positions used by the
  /// first advance()). Validates each mesh (throws mccd::Error naming mesh and index).
  explicit Scene(std::vector<TriMesh> meshes, SceneOptions options = {});
  ~Scene();
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;

  /// One step: every vertex moves linearly from `start` to `end` (one view per mesh).
  /// Throws mccd::Error, before any state changes, on a wrong mesh count, row count or a
  /// non-finite coordinate (naming start/end, mesh and vertex).
  StepResult step(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                  std::optional<Method> method = std::nullopt);
  /// One step from the last end positions (initially the meshes' positions) to `next`.
  StepResult advance(const std::vector<PositionsView>& next, std::optional<Method> method = std::nullopt);

  /// Single-mesh conveniences.
  StepResult step(const PositionsView& start, const PositionsView& end, std::optional<Method> method = std::nullopt) {
    return step(std::vector<PositionsView>{start}, std::vector<PositionsView>{end}, method);
  }
  StepResult advance(const PositionsView& next, std::optional<Method> method = std::nullopt) {
    return advance(std::vector<PositionsView>{next}, method);
  }

  std::size_t num_meshes() const;
  const TriMesh& mesh(std::size_t i) const;       ///< with its initial positions
  const MeshTopology& topology() const;           ///< of all meshes, global ids
  std::size_t vertex_offset(std::size_t mesh) const;
  std::size_t face_offset(std::size_t mesh) const;
  std::size_t edge_offset(std::size_t mesh) const;
  std::size_t orphan_vf_count() const;
  std::size_t orphan_ee_count() const;
  std::size_t bvh_depth() const;
  const SceneOptions& options() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace mccd
