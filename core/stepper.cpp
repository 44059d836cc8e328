#include <mccd/core/stepper.h>

#include <mccd/core/brute_force.h>
#include <mccd/parallel/front_tracking.h>
#include <mccd/parallel/phc.h>
#include <mccd/parallel/volume_update.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>

namespace mccd::detail {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void add_stats(WorkerOutputs& units, std::size_t n, StepStats& total) {
  for (std::size_t i = 0; i < n; ++i) total += units[i].stats;
}

/// Whether the ray from `o` along `d` may meet the first quarter's box of `v` (false only when
/// it certainly does not: the box is grown by 2^-30 of the largest magnitude involved, far
/// more than the relative error 2^-51 of each slab's parameters).
template <class Quarters>
bool ray_meets_box(const Quarters& v, const Vec3& o, const Vec3& d) {
  double enter = 0, leave = std::numeric_limits<double>::infinity();
  for (int s = 0; s < 3; ++s) {
    const double lo0 = v.lo(s)[0], hi0 = v.hi(s)[0];
    if (!(lo0 <= hi0)) return true;  // empty or NaN: no claim
    const double grow = 0x1p-30 * std::max({std::abs(lo0), std::abs(hi0), std::abs(o[s])}) + 0x1p-1000;
    const double lo = lo0 - grow, hi = hi0 + grow;
    if (d[s] == 0) {
      if (o[s] < lo || o[s] > hi) return false;
      continue;
    }
    double a = (lo - o[s]) / d[s], b = (hi - o[s]) / d[s];
    if (a > b) std::swap(a, b);
    enter = std::max(enter, a);
    leave = std::min(leave, b);
  }
  return !(enter > leave);
}
}  // namespace

template <BoundingVolume BV>
BvhTopology Stepper<BV>::build_bvh(const std::vector<Triangle>& faces, const std::vector<std::size_t>& face_offsets,
                                   const SceneOptions& options, const Positions& initial) {
  const unsigned leaf = options.leaf_size ? options.leaf_size : (options.bvh == BvhBuild::Median ? 1u : BvhTopology::kMaxLeaf);
  return BvhTopology(triangle_bounds(faces, initial), options.bvh, leaf, face_offsets, &faces);
}

template <BoundingVolume BV>
Stepper<BV>::Stepper(const SceneTopology& scene, const SceneOptions& options, const Positions& initial, BvhTopology bvh)
    : scene_(scene),
      options_(options),
      x0_(initial),
      x1_(initial),
      bvh_(std::move(bvh)),
      refit_plan_(bvh_,
                  [&](std::uint32_t n) {
                    const std::uint32_t m = bvh_.mesh_of_node(n);
                    return m != BvhTopology::kMixed && scene.mesh_options(m).is_static;
                  }),
      nodes_(bvh_.size()),
      owners_(bvh_, scene.topology()),
      lanes_(scene.representatives() == Representatives::Leaf ? LeafLanes<BV>(bvh_, owners_) : LeafLanes<BV>()),
      tests_(scene.topology(), swept_, x0_, x1_, query_, ConservativeCcd{CcdOptions{options.min_distance}}),
      culling_(options.self_culling && options.min_distance == 0 && scene.representatives() == Representatives::Leaf
                   ? SelfCulling(bvh_, scene)
                   : SelfCulling()),
      leaf_(scene, bvh_, owners_, nodes_, lanes_, tests_, &unchanged_, &culling_),
      bvtt_(bvh_, nodes_, scene, leaf_, query_, &culling_) {
  const MeshTopology& topo = scene.topology();
  // The large arrays' first touch (page faults and the kernel's zeroing) in parallel (the
  // scene constructs its stepper in its arena).
  auto chunks = [](std::size_t n, const auto& body) { static_for(n, 16384, body); };
  swept_.resize(topo, owners_.layout(), chunks);
  // What backing a page costs varies widely from page to page (in a virtual machine the host
  // backs it too): small chunks dealt out dynamically keep both threads busy to the end.
  auto touch_chunks = [](std::size_t n, const auto& body) {
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, n, 4096),
        [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); }, tbb::simple_partitioner());
  };
  swept_.first_touch(touch_chunks);
  first_touch(nodes_, touch_chunks);
  lanes_.first_touch(touch_chunks);
  lanes_.set_order(options.volume_order);
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
    const IndexRanges all_v{{0, topo.num_vertices()}};
    update_swept_volumes(swept_, topo, x0_, x1_, options_.min_distance, all_v);
    refit_plan_.run_static(bvh_, nodes_, [&](std::uint32_t n) { return leaf_volume(n); });
  }
  graph_ = std::make_unique<StepGraph>(StepGraph::Stages{[this] { update(); }, [this] { refit(); },
                                                         [this] { search(); }, [this] { self_pairs(); },
                                                         [this] { join(); }});
}

template <BoundingVolume BV>
StepResult Stepper<BV>::step(Method method, StepKind kind) {
  method_ = method;
  full_ = kind == StepKind::Full;
  // Leaves that repeat the previous step are skipped only right after a full step that
  // processed its leaf pairs; a query forgets it (its positions are not the scene's).
  if (full_ && scene_.representatives() == Representatives::Leaf)
    unchanged_.begin(bvh_.size(), scene_.topology().num_vertices(), repeatable_);
  else
    unchanged_.forget();
  repeatable_ = false;  // until this step completes
  query_.reset(kind);
  result_ = StepResult{};
  result_.stats.method = method;
  contacts_.clear();
  self_stats_ = {};
  if (options_.flow_graph && scene_.topology().num_faces() >= kGraphMinFaces) {
    graph_->run();
  } else {
    update();
    refit();
    search();
    self_pairs();
    join();
  }
  if (full_) {
    ++full_steps_;
    if (full_steps_ > 1) unchanged_.end();  // the first full step records no positions
    repeatable_ = method != Method::BruteForce && scene_.representatives() == Representatives::Leaf;
  }
  return std::move(result_);
}

template <BoundingVolume BV>
void Stepper<BV>::update() {
  const auto t = Clock::now();
  const SceneTopology::Ranges& moving = scene_.moving();
  // From the second full step on, each vertex against the previous step's positions (a
  // single step, like toi-check's, pays nothing for it); the volumes of those that repeat
  // hold from the previous step, which was a full one (UnchangedLeaves::active()).
  if (full_ && full_steps_ > 0 && scene_.representatives() == Representatives::Leaf)
    dynamic_for(scene_.topology().num_vertices(), 4096,
               [&](std::size_t b, std::size_t e) { unchanged_.compare(x0_, x1_, b, e); });
  update_swept_volumes(swept_, scene_.topology(), x0_, x1_, options_.min_distance, moving.vertices,
                       unchanged_.active() ? unchanged_.same() : nullptr);
  for (const auto& [b, e] : moving.vertices) result_.stats.updated_vertices += e - b;
  if (!lanes_.empty()) {
    // Every vertex's coarse volume on a grid that holds the step (the leaves' lanes are filled
    // from them when a leaf pair or the self stage first needs them).
    const Bounds3 b0 = bounding_box(x0_), b1 = bounding_box(x1_);
    const Vec3 lo = b0.min.cwiseMin(b1.min), hi = b0.max.cwiseMax(b1.max);
    if (lo.x() <= hi.x()) lanes_.begin(grid_.fit(lo.data(), hi.data()));
    dynamic_for(scene_.topology().num_vertices(), 8192,
                [&](std::size_t b, std::size_t e) { lanes_.quantize_vertices(b, e, swept_); });
  }
  result_.stats.t_update = seconds_since(t);
}

template <BoundingVolume BV>
void Stepper<BV>::refit() {
  const auto t = Clock::now();
  if (unchanged_.active())
    refit_plan_.run(bvh_, nodes_, [&](std::uint32_t n) {
      // a leaf whose corners all repeat keeps the volume the previous full step gave it
      return unchanged_.mark_leaf(n, owners_) ? nodes_[n] : leaf_volume(n);
    });
  else
    refit_plan_.run(bvh_, nodes_, [&](std::uint32_t n) { return leaf_volume(n); });
  result_.stats.refit_nodes = refit_plan_.nodes_refitted(bvh_);
  if (culling_.possible() && method_ != Method::BruteForce) {
    // A node's first-quarter box holds its triangles at the start of the step; the ray test
    // grows it by far more than the rounding of its double arithmetic before it rules a node
    // out.
    culling_.certify(bvh_, scene_.topology(), x0_, x1_, [this](std::uint32_t n, const Vec3& o, const Vec3& d) {
      return ray_meets_box(nodes_[n], o, d);
    });
    result_.stats.culled_patches = culling_.certified();
  } else {
    culling_.clear();
  }
  result_.stats.t_refit = seconds_since(t);
}

template <BoundingVolume BV>
typename Stepper<BV>::NodeVolume Stepper<BV>::leaf_volume(std::uint32_t node) const {
  NodeVolume v = NodeVolume::empty();
  for (std::uint32_t s = owners_.vertex_begin(node); s != owners_.vertex_begin(node + 1); ++s)
    v.merge(swept_.vertex_quarters_at(s));
  for (std::uint32_t i = owners_.foreign_begin(node); i != owners_.foreign_begin(node + 1); ++i)
    v.merge(swept_.vertex_quarters_at(owners_.foreign_corner(i)));
  return v;
}

template <BoundingVolume BV>
void Stepper<BV>::search() {
  const auto t = Clock::now();
  StepStats& st = result_.stats;
  switch (method_) {
    case Method::BruteForce:
      serial_.clear();
      brute_force(scene_, bvh_, nodes_, swept_, tests_, serial_);
      flush(serial_, contacts_);
      st += serial_.stats;
      break;
    case Method::Traverse:
      traverse_serial<false>(bvtt_, serial_, contacts_);
      st += serial_.stats;
      break;
    case Method::Phc:
      traverse_phc<false>(bvtt_, units_, contacts_);
      add_stats(units_, units_.size(), st);
      break;
    case Method::Fbd:
      if (query_.kind() == StepKind::Full)
        search_fbd();
      else
        search_fbd_query();
      break;
  }
  st.t_front = seconds_since(t);
}

template <BoundingVolume BV>
void Stepper<BV>::search_fbd() {
  StepStats& st = result_.stats;
  if (front_.needs_build()) {
    traverse_phc<true>(bvtt_, units_, contacts_);
    add_stats(units_, units_.size(), st);
    front_.build(units_);
    st.rebuilds = 1;
  } else {
    const std::size_t n = track_front(bvtt_, front_, units_, contacts_);
    add_stats(units_, n, st);
    front_.advance(units_, n, options_.rebuild_sprout_ratio, options_.rebuild_invalid_ratio);
  }
  std::size_t bytes = front_.bytes();
  for (const WorkerOutput& o : units_) bytes += o.front.capacity() * sizeof(NodePair);
  if (options_.max_front_bytes != 0 && bytes > options_.max_front_bytes) {
    // Over the cap: dropped rather than kept and grown; the next step rebuilds it.
    front_.release();
    for (WorkerOutput& o : units_) o.front = std::vector<NodePair>();
    bytes = 0;
  }
  st.front_size = front_.size();
  st.front_bytes = bytes;
}

template <BoundingVolume BV>
void Stepper<BV>::search_fbd_query() {
  StepStats& st = result_.stats;
  if (front_.needs_build()) {
    traverse_phc<false>(bvtt_, units_, contacts_);
    add_stats(units_, units_.size(), st);
  } else {
    const std::size_t n = track_front(bvtt_, front_, units_, contacts_, /*readonly=*/true);
    add_stats(units_, n, st);
  }
}

template <BoundingVolume BV>
void Stepper<BV>::self_pairs() {
  if (method_ == Method::BruteForce) return;  // brute force already covers every pair
  const auto t = Clock::now();
  // Fixed blocks of self units (16 leaves of up to 21 triangles: small scenes still spread
  // over many threads), each with its own output, joined in block order.
  constexpr std::size_t kBlock = 16;
  const std::size_t units = leaf_.num_self_units(), n = (units + kBlock - 1) / kBlock;
  if (self_units_.size() < n) self_units_.resize(n);
  auto run = [&](std::size_t b) {
    WorkerOutput& o = self_units_[b];
    o.clear();
    leaf_.process_self(b * kBlock, std::min(units, (b + 1) * kBlock), o);
    flush(o, contacts_);
  };
  if (n <= kSerialBlocks)
    for (std::size_t b = 0; b < n; ++b) run(b);  // as in front tracking: not worth a thread
  else
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t b = r.begin(); b != r.end(); ++b) run(b);
    });
  add_stats(self_units_, n, self_stats_);
  self_stats_.t_orphans = seconds_since(t);
}

template <BoundingVolume BV>
void Stepper<BV>::join() {
  const auto t = Clock::now();
  result_.stats += self_stats_;
  join_contacts(contacts_, join_scratch_, scene_, result_);
  result_.stats.t_contacts = seconds_since(t);
}

template class Stepper<Kdop18>;
template class Stepper<Aabb>;

}  // namespace mccd::detail
