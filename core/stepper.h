#pragma once
/// @file Internal: all per-step state of a scene for one bounding-volume type, and the stages of
/// a step.
///
/// A step (DESIGN "The pipeline of one step"), run by the flow graph of parallel/step_graph.h:
///  1. update: the positions of the step's two ends become swept volumes per vertex, edge and
///     face (parallel/volume_update.h);
///  2. refit: the BVH's node volumes, bottom-up under a static partition (parallel/refit.h);
///     then the patches certified to hold no self-collision this step (core/self_culling.h);
///  3. search, by method: brute force (core/brute_force.h); a serial traversal from the root;
///     PHC (parallel/phc.h); or FBD: front tracking in parallel blocks (parallel/
///     front_tracking.h), building the front from the root first when the rebuild rule says
///     so (core/bvtt_front.h). Leaf pairs and elementary tests run where the traversal meets
///     them (core/leaf_pairs.h): traversal and narrow phase are one stage;
///  4. self, beside 3: the pairs no BVTT pair node holds, in parallel blocks: each leaf's own
///     pairs (leaf rule), or the orphan set and the pairs inside leaves (canonical rule);
///  5. join: the contacts into the canonical order (parallel/contact_buffer.h).
/// Every stage writes only its own outputs (per block, per task, per stage); the join reads
/// them in a fixed order, so a step's result does not depend on the thread count.
#include <chrono>
#include <memory>
#include <vector>

#include <mccd/core/bvtt.h>
#include <mccd/core/bvtt_front.h>
#include <mccd/core/leaf_pairs.h>
#include <mccd/core/options.h>
#include <mccd/core/query.h>
#include <mccd/core/scene_topology.h>
#include <mccd/core/self_culling.h>
#include <mccd/parallel/contact_buffer.h>
#include <mccd/parallel/refit.h>
#include <mccd/parallel/step_graph.h>

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
  /// (`kind` other than Full) reads the front but never changes it.
  StepResult step(Method method, StepKind kind = StepKind::Full);

  std::size_t bvh_depth() const { return bvh_.depth(); }
  std::size_t bvh_size() const { return bvh_.size(); }
  /// Forgets the front (the next fbd step rebuilds it from the root).
  void invalidate_front() { front_.invalidate(); }

 private:
  using Tests = FeatureTests<BV>;
  using Leaf = LeafPairs<BV>;
  using NodeVolume = QuarterVolume<BV>;
  /// Smaller scenes call the stages in sequence (SceneOptions::flow_graph).
  static constexpr std::size_t kGraphMinFaces = 8192;
  using Clock = std::chrono::steady_clock;

  void update();
  void refit();
  /// A leaf's quarter volumes: the merge of its corners' (owned, then the others'), each once.
  NodeVolume leaf_volume(std::uint32_t node) const;
  void search();
  void self_pairs();
  void join();
  void search_fbd();
  void search_fbd_query();

  const SceneTopology& scene_;
  SceneOptions options_;
  Positions x0_, x1_;
  BvhTopology bvh_;
  RefitPlan refit_plan_;
  LargeVector<NodeVolume> nodes_;  ///< per BVH node: its quarter volumes
  LeafOwnership owners_;   ///< the leaf rule's owners; also the volumes' storage layout
  SweptVolumes<BV> swept_;
  LeafLanes<BV> lanes_;    ///< leaf rule: the leaves' coarse volumes in lanes, filled as used
  GridKeeper<BV::kSlabs> grid_;  ///< their grid
  QueryState query_;
  Tests tests_;
  UnchangedLeaves unchanged_;  ///< leaves that repeat the previous full step (leaf rule)
  SelfCulling culling_;        ///< patches certified free of self-collision (leaf rule)
  Leaf leaf_;
  Bvtt<NodeVolume, Leaf> bvtt_;
  BvttFront front_;

  // the current step
  Method method_ = Method::Fbd;
  bool full_ = false;             ///< a full step (not a query)
  std::uint64_t full_steps_ = 0;  ///< full steps completed
  bool repeatable_ = false;       ///< the last step was a full step that processed its leaf pairs
  StepResult result_;
  WorkerOutputs units_;  ///< per front block, or per PHC task
  WorkerOutputs self_units_;  ///< per block of the self stage
  WorkerOutput serial_;
  StepStats self_stats_;
  ContactBuffer contacts_;
  JoinScratch join_scratch_;  ///< kept from step to step
  std::unique_ptr<StepGraph> graph_;
};

extern template class Stepper<Kdop18>;
extern template class Stepper<Aabb>;

}  // namespace mccd::detail
