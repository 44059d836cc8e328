#pragma once
/// @file Internal: all per-step state of a scene for one bounding-volume type. The stages of a
/// step, in order, and what runs beside what, are written down once, in stepper.cpp.
#include <chrono>
#include <memory>
#include <vector>

#include <mccd/core/bvtt.h>
#include <mccd/core/leaf_pairs.h>
#include <mccd/core/options.h>
#include <mccd/core/query.h>
#include <mccd/core/scene_topology.h>
#include <mccd/core/self_culling.h>
#include <mccd/parallel/contact_buffer.h>
#include <mccd/parallel/refit.h>
#include <mccd/parallel/search.h>
#include <mccd/parallel/self_stage.h>
#include <mccd/parallel/step_graph.h>
#include <mccd/parallel/update.h>

namespace mccd::detail {

template <BoundingVolume BV>
class Stepper {
 public:
  /// With the scene's BVH from build_bvh() (the scene builds it beside its connectivity) and
  /// the initial positions (global ids).
  Stepper(const SceneTopology& scene, const SceneOptions& options, const Positions& initial, BvhTopology bvh);
  /// The BVH the options ask for, over the triangles `faces` (global vertex ids) at `initial`;
  /// `face_offsets`: each mesh's first face (SceneFaces).
  static BvhTopology build_bvh(const std::vector<Triangle>& faces, const std::vector<std::size_t>& face_offsets,
                               const SceneOptions& options, const Positions& initial);

  /// The step's start and end positions, global vertex ids, filled by the caller before step().
  Positions& start() { return x0_; }
  Positions& end() { return x1_; }
  const Positions& end() const { return x1_; }

  /// Runs one step from start() to end() with `method` in the calling thread's arena. A query
  /// (`kind` other than Full) reads the front but never changes it. `continues`: start() is
  /// bit for bit the end of the last full step (then what repeats that step may be skipped:
  /// UnchangedLeaves). `storage` (nullptr: none): a contact list (a caller's kept result's)
  /// whose storage the result's contacts take over: written over rather than allocated anew.
  StepResult step(Method method, StepKind kind = StepKind::Full, bool continues = false,
                  std::vector<Contact>* storage = nullptr);

  std::size_t bvh_depth() const { return bvh_.depth(); }
  std::size_t bvh_size() const { return bvh_.size(); }
  /// Forgets the front (the next fbd step rebuilds it from the root).
  void invalidate_front() { search_.invalidate_front(); }
  const BvttFront& front() const { return search_.front(); }
  /// The last update's volumes, the BVH, its leaves' owners and its node volumes (for the
  /// tests).
  const UpdateState<BV>& volumes() const { return volumes_; }
  const BvhTopology& bvh() const { return bvh_; }
  const LeafOwnership& owners() const { return owners_; }
  const LargeVector<QuarterVolume<BV>>& node_volumes() const { return nodes_; }

 private:
  using Tests = FeatureTests<BV>;
  using Leaf = LeafPairs<BV>;
  using NodeVolume = QuarterVolume<BV>;
  /// Smaller scenes call the stages in sequence (SceneOptions::flow_graph).
  static constexpr std::size_t kGraphMinFaces = 8192;

  // The stages, each timed into the step's counters (stepper.cpp).
  void update();
  void refit();
  void search();
  void self();
  void join();

  const SceneTopology& scene_;
  SceneOptions options_;
  Positions x0_, x1_;
  BvhTopology bvh_;
  RefitPlan refit_plan_;
  LargeVector<NodeVolume> nodes_;  ///< per BVH node: its quarter volumes
  LeafOwnership owners_;   ///< the leaf rule's owners; also the volumes' storage layout
  UpdateState<BV> volumes_;  ///< swept volumes, the leaves' coarse lanes and their grid
  QueryState query_;
  Tests tests_;
  UnchangedLeaves unchanged_;  ///< leaves that repeat the previous full step (leaf rule)
  SelfCulling culling_;        ///< patches certified free of self-collision (leaf rule)
  Leaf leaf_;
  Bvtt<NodeVolume, Leaf> bvtt_;
  SearchStage search_;
  SelfStage self_;

  // the current step
  Method method_ = Method::Fbd;
  bool full_ = false;             ///< a full step (not a query)
  std::uint64_t full_steps_ = 0;  ///< full steps completed
  bool repeatable_ = false;       ///< the last step was a full step that processed its leaf pairs
  bool graph_run_ = false;         ///< this step runs through the flow graph
  bool running_ = false;           ///< a step is under way (checked: never two at once)
  bool kept_storage_ = false;      ///< the result's contacts reuse a caller's storage
  StepResult result_;
  StepStats self_stats_;  ///< the self stage's, added at the join (it runs beside the search)
  ContactBuffer contacts_;
  JoinScratch join_scratch_;  ///< kept from step to step
  std::unique_ptr<StepGraph> graph_;
};

extern template class Stepper<Kdop18>;
extern template class Stepper<Aabb>;

}  // namespace mccd::detail
