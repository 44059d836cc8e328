#pragma once
/// @file The public API: a scene of deforming triangle meshes, stepped over time.
///
///   mccd::Scene scene({cloth, body});                 // built once
///   auto r = scene.step({cloth_t0, body_t0}, {cloth_t1, body_t1});
///   for (const mccd::Contact& c : r.contacts) ...     // sorted, earliest toi in r.earliest_toi
///   r = scene.advance({cloth_t2, body_t2});           // t1 -> t2
///
/// Thread safety: one step at a time per scene (a second concurrent call is refused with
/// mccd::Error); different scenes are independent and may be stepped concurrently. A step
/// runs its parallel stages in the caller's TBB arena, or in SceneOptions::arena, and may be
/// called from inside the host's own parallel algorithms and flow graphs.
#include <memory>
#include <optional>
#include <vector>

#include <mccd/core/contact.h>
#include <mccd/core/options.h>
#include <mccd/core/stats.h>
#include <mccd/geometry/mesh.h>
#include <mccd/geometry/positions.h>
#include <mccd/geometry/topology.h>

namespace mccd {

class Scene {
 public:
  /// Builds the scene from meshes (their positions are the initial positions used by the
  /// first advance()). Validates the options and each mesh (throws mccd::Error naming the
  /// option, or the mesh and the index).
  explicit Scene(std::vector<TriMesh> meshes, SceneOptions options = {});
  ~Scene();
  Scene(Scene&&) noexcept;
  Scene& operator=(Scene&&) noexcept;

  /// One step: every vertex moves linearly from `start` to `end` (one view per mesh; see
  /// PositionsView for the accepted forms). Throws mccd::Error, before any state changes, on
  /// a wrong mesh count, a wrong row or column count, a non-finite coordinate (naming start or
  /// end, the mesh and the vertex), an out-of-range method, or a step of this scene already
  /// running in another thread.
  StepResult step(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                  std::optional<Method> method = std::nullopt);
  /// One step from the last end positions (initially the meshes' positions) to `next`.
  StepResult advance(const std::vector<PositionsView>& next, std::optional<Method> method = std::nullopt);

  /// The same steps into `result`, whose contact list's storage is reused: a host that steps
  /// every frame keeps one StepResult and saves the fresh memory of a new list each step (its
  /// pages' first touch, a large part of joining a step's contacts). `result` is overwritten;
  /// a refused step (the errors above) leaves it as it was, a failure inside the engine (out of
  /// memory) leaves it empty.
  void step(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end, StepResult& result,
            std::optional<Method> method = std::nullopt);
  void advance(const std::vector<PositionsView>& next, StepResult& result, std::optional<Method> method = std::nullopt);

  /// Single-mesh conveniences.
  StepResult step(const PositionsView& start, const PositionsView& end, std::optional<Method> method = std::nullopt) {
    return step(std::vector<PositionsView>{start}, std::vector<PositionsView>{end}, method);
  }
  StepResult advance(const PositionsView& next, std::optional<Method> method = std::nullopt) {
    return advance(std::vector<PositionsView>{next}, method);
  }
  void step(const PositionsView& start, const PositionsView& end, StepResult& result,
            std::optional<Method> method = std::nullopt) {
    step(std::vector<PositionsView>{start}, std::vector<PositionsView>{end}, result, method);
  }
  void advance(const PositionsView& next, StepResult& result, std::optional<Method> method = std::nullopt) {
    advance(std::vector<PositionsView>{next}, result, method);
  }

  /// Simulator queries on the step from `start` to `end` (IPC Toolkit users know them as
  /// is_step_collision_free and compute_collision_free_stepsize). Each leaves the scene as it
  /// was: the last end positions used by advance() and the front are unchanged (the front is
  /// read, when it exists, to find the candidates faster). Input is checked as by step().
  /// `stats`, when given, receives what the query did.
  ///
  /// Whether no feature pair touches during the step. Stops at the first certified contact:
  /// no contact list, no sort; much cheaper than step() when a contact exists early.
  bool is_collision_free(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                         StepStats* stats = nullptr);
  /// The earliest conservative time of impact in [0, 1] (+inf when collision free), equal to
  /// step(start, end).earliest_toi; pairs that cannot beat the best time found so far are
  /// skipped before their elementary test.
  double earliest_impact(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                         StepStats* stats = nullptr);
  /// The broad-phase candidates, for hosts with their own narrow phase: every feature pair the
  /// elementary tests would see (each once, behind the same volume tests), untested. `toi` of
  /// each is a lower bound of any contact time: the start of the first quarter of the step in
  /// which the pair's swept volumes overlap (0, 0.25, 0.5 or 0.75). Canonical order.
  std::vector<Contact> candidates(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                                  StepStats* stats = nullptr);

  /// Single-mesh conveniences.
  bool is_collision_free(const PositionsView& start, const PositionsView& end, StepStats* stats = nullptr) {
    return is_collision_free(std::vector<PositionsView>{start}, std::vector<PositionsView>{end}, stats);
  }
  double earliest_impact(const PositionsView& start, const PositionsView& end, StepStats* stats = nullptr) {
    return earliest_impact(std::vector<PositionsView>{start}, std::vector<PositionsView>{end}, stats);
  }
  std::vector<Contact> candidates(const PositionsView& start, const PositionsView& end, StepStats* stats = nullptr) {
    return candidates(std::vector<PositionsView>{start}, std::vector<PositionsView>{end}, stats);
  }

  std::size_t num_meshes() const;
  const TriMesh& mesh(std::size_t i) const;       ///< with its initial positions
  const MeshTopology& topology() const;           ///< of all meshes, global ids
  std::size_t vertex_offset(std::size_t mesh) const;
  std::size_t face_offset(std::size_t mesh) const;
  std::size_t edge_offset(std::size_t mesh) const;
  /// The orphan set of the canonical rule (0 under the leaf rule, which has none).
  std::size_t orphan_vf_count() const;
  std::size_t orphan_ee_count() const;
  std::size_t bvh_depth() const;
  const SceneOptions& options() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace mccd
