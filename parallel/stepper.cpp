/// @file One step of a scene, stage by stage (DESIGN "The pipeline of one step"):
///
///   1. update  (parallel/update.h): the positions of the step's two ends become swept volumes
///      per vertex, and coarse volumes for the leaf rule's lanes;
///   2. refit   (parallel/refit.h): the BVH's node volumes, bottom-up under a static partition;
///      then the patches certified free of self-collision this step (core/self_culling.h);
///   3. search  (parallel/search.h): the method's candidate pairs (brute force, a serial
///      traversal, PHC, or FBD: the front tracked in parallel blocks), their leaf pairs and
///      elementary tests where the traversal meets them;
///   4. self    (parallel/self_stage.h), beside 3: the pairs no BVTT pair node holds;
///   5. join    (parallel/contact_buffer.h): the contacts into the canonical order.
///
/// Large scenes run the stages as the flow graph of parallel/step_graph.h (3 and 4 at once);
/// small ones call them in this order on the calling thread. Every stage writes only its own
/// outputs (per block, per task, per stage) and the join reads them in a fixed order, so a
/// step's result does not depend on the thread count. The set-up (the constructor) builds the
/// BVH's companions through the engine's executor and first-touches the large arrays in
/// parallel.
#include <mccd/parallel/stepper.h>

#include <mccd/core/brute_force.h>
#include <mccd/geometry/assert.h>
#include <mccd/parallel/tbb_executor.h>

#include <algorithm>

namespace mccd::detail {

template <BoundingVolume BV>
BvhTopology Stepper<BV>::build_bvh(const std::vector<Triangle>& faces, const std::vector<std::size_t>& face_offsets,
                                   const SceneOptions& options, const Positions& initial) {
  const unsigned leaf = options.leaf_size ? options.leaf_size : (options.bvh == BvhBuild::Median ? 1u : BvhTopology::kMaxLeaf);
  return BvhTopology(triangle_bounds(faces, initial, tbb_executor()), options.bvh, leaf, face_offsets, &faces,
                     tbb_executor());
}

template <BoundingVolume BV>
Stepper<BV>::Stepper(const SceneTopology& scene, const SceneOptions& options, const Positions& initial, BvhTopology bvh)
    : scene_(scene),
      options_(options),
      x0_(backed_copy(initial)),  // pages backed at once
      x1_(backed_copy(initial)),
      bvh_(std::move(bvh)),
      refit_plan_(bvh_,
                  [&](std::uint32_t n) {
                    const std::uint32_t m = bvh_.mesh_of_node(n);
                    return m != BvhTopology::kMixed && scene.mesh_options(m).is_static;
                  }),
      nodes_(bvh_.size()),
      tests_(scene.topology(), volumes_.swept, x0_, x1_, query_, ConservativeCcd{CcdOptions{options.min_distance}}),
      leaf_(scene, bvh_, owners_, nodes_, volumes_.lanes, tests_, &unchanged_, &culling_),
      bvtt_(bvh_, nodes_, scene, leaf_, query_, &culling_),
      search_(FrontRules{options.rebuild_sprout_ratio, options.rebuild_invalid_ratio, options.max_front_bytes}) {
  // The leaf rule's owners and lanes beside the self-culling certificates' patches: each has
  // serial parts that the other's loops fill (the members hold nothing until here; the
  // objects constructed above keep references to them only).
  const bool leaf_rule = scene.representatives() == Representatives::Leaf;
  tbb_executor().invoke(
      [&] {
        owners_ = LeafOwnership(bvh_, scene.topology(), tbb_executor());
        if (leaf_rule) volumes_.lanes = LeafLanes<BV>(bvh_, owners_, tbb_executor());
      },
      [&] {
        if (options.self_culling && options.min_distance == 0 && leaf_rule)
          culling_ = SelfCulling(bvh_, scene, tbb_executor());
      });
  const MeshTopology& topo = scene.topology();
  // The large arrays' first touch (page faults and the kernel's zeroing) in parallel (the
  // scene constructs its stepper in its arena).
  auto chunks = [](std::size_t n, const auto& body) { static_for(n, 16384, body); };
  volumes_.swept.resize(topo, owners_.layout(), chunks);
  // What backing a page costs varies widely from page to page (in a virtual machine the host
  // backs it too): small chunks dealt out dynamically keep both threads busy to the end.
  auto touch_chunks = [](std::size_t n, const auto& body) { dynamic_for(n, 4096, body); };
  volumes_.swept.first_touch(touch_chunks);
  first_touch(nodes_, touch_chunks);
  volumes_.lanes.first_touch(touch_chunks);
  volumes_.lanes.set_order(options.volume_order);
  // With static meshes, every volume once at the initial positions: the static meshes' stay
  // as they are (the others are recomputed by every step).
  bool any_static = false;
  for (std::size_t m = 0; m < scene.num_meshes(); ++m) any_static = any_static || scene.mesh_options(m).is_static;
  if (any_static) {
    // Their leaves always repeat the previous step (core/unchanged_leaves.h).
    std::vector<std::uint8_t> fixed(bvh_.size(), 0);
    for (std::uint32_t n = 0; n < bvh_.size(); ++n) {
      const std::uint32_t m = bvh_.mesh_of_node(n);
      fixed[n] = bvh_.leaf(n) && m != BvhTopology::kMixed && scene.mesh_options(m).is_static;
    }
    unchanged_.set_static(std::move(fixed));
    update_swept_volumes(volumes_.swept, topo, x0_, x1_, options_.min_distance);
    // from now on every step keeps them
    volumes_.fixed.assign(topo.num_vertices(), 1);
    for (const auto& [b, e] : scene.moving().vertices)
      std::fill(volumes_.fixed.begin() + std::ptrdiff_t(b), volumes_.fixed.begin() + std::ptrdiff_t(e), 0);
    refit_plan_.run_static(bvh_, nodes_, [&](std::uint32_t n) { return leaf_volume(owners_, volumes_.swept, n); });
  }
  graph_ = std::make_unique<StepGraph>(StepGraph::Stages{[this] { update(); }, [this] { refit(); },
                                                         [this] { search(); }, [this] { self(); },
                                                         [this] { join(); }});
}

template <BoundingVolume BV>
StepResult Stepper<BV>::step(Method method, StepKind kind, bool continues, std::vector<Contact>* storage) {
  MCCD_ASSERT(!running_, "a step of this stepper is already running");
  running_ = true;
  struct Done {
    bool& running;
    ~Done() { running = false; }
  } done{running_};
  method_ = method;
  full_ = kind == StepKind::Full;
  // The parallel methods run a heavy unit's queues of feature pairs in parallel pieces; the
  // serial traversal and brute force keep theirs on one thread.
  tests_.set_executor(method == Method::Fbd || method == Method::Phc ? &tbb_executor() : nullptr);
  // Leaves that repeat the previous step are skipped only right after a full step that
  // processed its leaf pairs; a query forgets it (its positions are not the scene's).
  if (full_ && scene_.representatives() == Representatives::Leaf)
    unchanged_.begin(bvh_.size(), scene_.topology().num_vertices(), repeatable_, continues);
  else
    unchanged_.forget();
  repeatable_ = false;  // until this step completes
  query_.reset(kind);
  result_ = StepResult{};
  kept_storage_ = storage != nullptr;
  if (storage) result_.contacts.swap(*storage);
  result_.stats.method = method;
  contacts_.clear();
  self_stats_ = {};
  graph_run_ = options_.flow_graph && scene_.topology().num_faces() >= kGraphMinFaces;
  if (graph_run_) {
    graph_->run();  // the same stages: 1, 2, then 3 beside 4, then 5
  } else {
    update();  // 1
    refit();   // 2
    search();  // 3
    self();    // 4
    join();    // 5
  }
  if (full_) {
    ++full_steps_;
    if (scene_.representatives() == Representatives::Leaf) unchanged_.end();
    repeatable_ = method != Method::BruteForce && scene_.representatives() == Representatives::Leaf;
  }
  return std::move(result_);
}

template <BoundingVolume BV>
void Stepper<BV>::update() {
  WorkSpanRecorder recorder;
  const StageClock clock(options_.work_span ? &recorder : nullptr);
  // Full steps note each vertex's motion as the update reads it (UnchangedLeaves::note).
  const bool track = full_ && scene_.representatives() == Representatives::Leaf;
  update_stage(scene_, x0_, x1_, options_.min_distance, track ? &unchanged_ : nullptr, volumes_, result_.stats);
  result_.stats.t_update = clock.seconds();
  result_.stats.ws_update = clock.work_span(result_.stats.t_update);
}

template <BoundingVolume BV>
void Stepper<BV>::refit() {
  WorkSpanRecorder recorder;
  const StageClock clock(options_.work_span ? &recorder : nullptr);
  refit_stage(refit_plan_, bvh_, owners_, volumes_.swept, unchanged_, nodes_, method_ != Method::BruteForce, culling_,
              scene_.topology(), x0_, x1_, result_.stats);
  result_.stats.t_refit = clock.seconds();
  result_.stats.ws_refit = clock.work_span(result_.stats.t_refit);
}

template <BoundingVolume BV>
void Stepper<BV>::search() {
  WorkSpanRecorder recorder;
  const StageClock clock(options_.work_span ? &recorder : nullptr);
  auto oracle = [&](WorkerOutput& out) { brute_force(scene_, bvh_, nodes_, volumes_.swept, tests_, out); };
  search_.run(method_, query_.kind(), bvtt_, oracle, contacts_, result_.stats);
  result_.stats.t_front = clock.seconds();
  result_.stats.ws_search = clock.work_span(result_.stats.t_front);
}

template <BoundingVolume BV>
void Stepper<BV>::self() {
  if (method_ == Method::BruteForce) return;  // brute force already covers every pair
  WorkSpanRecorder recorder;
  const StageClock clock(options_.work_span ? &recorder : nullptr);
  self_.run(leaf_, contacts_, self_stats_);
  self_stats_.t_self = clock.seconds();
  self_stats_.ws_self = clock.work_span(self_stats_.t_self);
}

template <BoundingVolume BV>
void Stepper<BV>::join() {
  WorkSpanRecorder recorder;
  const StageClock clock(options_.work_span ? &recorder : nullptr);
  result_.stats += self_stats_;
  // The search and the self stage: one after the other, or beside each other in the graph.
  StepStats& st = result_.stats;
  st.ws_branch = {st.ws_search.work + st.ws_self.work,
                  graph_run_ ? std::max(st.ws_search.span, st.ws_self.span) : st.ws_search.span + st.ws_self.span};
  join_contacts(contacts_, join_scratch_, scene_, result_, true, kept_storage_);
  st.t_contacts = clock.seconds();
  st.ws_join = clock.work_span(st.t_contacts);
}

template class Stepper<Kdop18>;
template class Stepper<Aabb>;

}  // namespace mccd::detail
