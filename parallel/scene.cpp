// The public Scene: validation, positions in, and the stepper of the scene's bounding volume.
#include <mccd/parallel/scene.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <oneapi/tbb/parallel_invoke.h>
#include <oneapi/tbb/task_arena.h>

#include <mccd/core/scene_topology.h>
#include <mccd/geometry/large_allocator.h>
#include <mccd/geometry/error.h>
#include <mccd/parallel/stepper.h>
#include <mccd/parallel/tbb_executor.h>

namespace mccd {

namespace {
using Clock = std::chrono::steady_clock;

/// Refuses a second concurrent step of one scene instead of corrupting it.
class StepGuard {
 public:
  explicit StepGuard(std::atomic<bool>& busy) : busy_(busy) {
    if (busy_.exchange(true, std::memory_order_acquire))
      throw Error("Scene: a step of this scene is already running in another thread; a scene steps one call at a "
                  "time (serialise the calls, or use one Scene per thread)");
  }
  ~StepGuard() { busy_.store(false, std::memory_order_release); }
  StepGuard(const StepGuard&) = delete;
  StepGuard& operator=(const StepGuard&) = delete;

 private:
  std::atomic<bool>& busy_;
};
}  // namespace

struct Scene::Impl {
  SceneOptions options;
  std::vector<TriMesh> meshes;
  std::unique_ptr<detail::SceneTopology> topo;
  std::unique_ptr<detail::Stepper<Kdop18>> dop;
  std::unique_ptr<detail::Stepper<Aabb>> aabb;
  std::atomic<bool> busy{false};
  Positions last_end;  ///< the end positions of the last step (initially the meshes'), for advance()
  /// take_in()'s pieces (a mesh's vertices [b, e) each) and tasks (the first piece of each,
  /// then the end), kept from step to step.
  struct InputPiece {
    std::uint32_t mesh;
    std::size_t b, e;
    bool compare;  ///< a static mesh's positions, compared with its own (not copied)
  };
  std::vector<InputPiece> input_pieces;
  std::vector<std::size_t> input_tasks;

  /// Runs `f` in the scene's arena (the caller's when none is set), isolated: while this thread
  /// waits inside, it takes only `f`'s own tasks, never an outer task of the host.
  template <class F>
  auto in_arena(const F& f) {
    auto body = [&] { return tbb::this_task_arena::isolate(f); };
    return options.arena ? options.arena->execute(body) : body();
  }

  Impl(std::vector<TriMesh> ms, SceneOptions opt) : options(opt), meshes(std::move(ms)) {
    validate(options);
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      if (meshes[m].name.empty()) meshes[m].name = "mesh " + std::to_string(m);
      validate_mesh(meshes[m]);
    }
    const detail::SceneFaces faces = detail::scene_faces(meshes);
    detail::reserve_backed(last_end.xyz(), 3 * faces.vertex_offsets.back());  // written in full below
    last_end.resize(faces.vertex_offsets.back());
    for (std::size_t m = 0; m < meshes.size(); ++m)
      std::copy(meshes[m].vertices.xyz().begin(), meshes[m].vertices.xyz().end(),
                last_end.xyz().begin() + static_cast<std::ptrdiff_t>(3 * faces.vertex_offsets[m]));
    // The set-up in the scene's arena, isolated like a step: the BVH build (parallel itself)
    // beside the connectivity's (serial), then the stepper's arrays (first touched in parallel).
    in_arena([&] {
      if (options.volume == VolumeKind::Kdop18)
        dop = make_stepper<Kdop18>(faces);
      else
        aabb = make_stepper<Aabb>(faces);
    });
  }

  template <BoundingVolume BV>
  std::unique_ptr<detail::Stepper<BV>> make_stepper(const detail::SceneFaces& faces) {
    BvhTopology bvh;
    tbb::parallel_invoke(
        [&] { bvh = detail::Stepper<BV>::build_bvh(faces.faces, faces.face_offsets, options, last_end); },
        [&] {
          topo = std::make_unique<detail::SceneTopology>(faces, options.meshes, resolved_representatives(options));
        });
    return std::make_unique<detail::Stepper<BV>>(*topo, options, last_end, std::move(bvh));
  }

  /// Scene::step and Scene::advance; `into` (nullptr: none): the result whose contacts'
  /// storage the step reuses (run()).
  StepResult full_step(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                       std::optional<Method> method, StepResult* into);
  StepResult advance(const std::vector<PositionsView>& next, std::optional<Method> method, StepResult* into);
  StepResult query(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                   detail::StepKind kind, StepStats* stats);

  Positions& start() { return dop ? dop->start() : aabb->start(); }
  Positions& end() { return dop ? dop->end() : aabb->end(); }

  /// Vertices per chunk of the positions' check and copy (each step reads every position
  /// once: serial passes were a millisecond a step at 100K vertices, most of what a 16-thread
  /// step spent outside the engine; a chunk is short next to a 16-thread step).
  static constexpr std::size_t kPositionsGrain = 2048;

  /// Whether every coordinate of the `n` doubles at p is finite. A double is not finite when
  /// its exponent bits are all ones: adding one at the exponent's lowest bit then carries into
  /// the sign bit. Integer operations the compiler puts in vector lanes, with no branch.
  static bool all_finite(const double* p, std::size_t n) {
    constexpr std::uint64_t kExponent = 0x7ff0000000000000ULL, kLowest = 0x0010000000000000ULL;
    std::uint64_t carries = 0;
    for (std::size_t i = 0; i < n; ++i) {
      std::uint64_t bits;
      std::memcpy(&bits, p + i, sizeof bits);
      carries |= (bits & kExponent) + kLowest;
    }
    return carries >> 63 == 0;
  }

  /// Checks `views` (`which`: the argument, for errors) and copies them into `dst` (global ids),
  /// converting float to double. Every shape first; then the moving meshes' vertices in one
  /// parallel loop in the scene's arena, in tasks of about kPositionsGrain vertices (a long
  /// mesh in several, small meshes together): each piece is copied, then checked where it lies
  /// in cache; the positions given for a static mesh are compared with its own in the same
  /// loop. Throws naming the first fault (the number of arrays, a mesh's vertex count or
  /// columns, a static mesh moved, then the first mesh with a coordinate that is not finite);
  /// `dst` is then the scene's scratch, rewritten in full by the next step, and nothing else
  /// has changed. With `same_as`: returns whether every copied position is bit for bit the one
  /// there (a static mesh's never change). `ws` (nullptr: not measured): the loop's work and
  /// span are added there.
  bool take_in(const std::vector<PositionsView>& views, const char* which, Positions& dst,
               const Positions* same_as = nullptr, WorkSpan* ws = nullptr) {
    if (views.size() != meshes.size())
      throw Error(std::string(which) + ": " + std::to_string(views.size()) + " position arrays for " +
                  std::to_string(meshes.size()) + " meshes");
    auto what = [&](std::size_t m) {
      return std::string(which) + ", mesh " + std::to_string(m) + " (" + meshes[m].name + ")";
    };
    // The shapes, and the pieces of the loop.
    std::vector<InputPiece>& pieces = input_pieces;
    std::vector<std::size_t>& tasks = input_tasks;  // the first piece of each task, then the end
    pieces.clear();
    tasks.assign(1, 0);
    std::size_t in_task = 0;
    for (std::size_t m = 0; m < views.size(); ++m) {
      const PositionsView& v = views[m];
      const std::size_t nv = meshes[m].num_vertices();
      const bool compare = topo->mesh_options(m).is_static;  // no positions, or its own, unchanged
      if (compare && v.rows() == 0) continue;
      if (v.cols() != 3 || v.rows() != nv || (nv > 0 && v.data() == nullptr))
        validate_positions_shape(v, nv, what(m));  // throws, naming the fault
      for (std::size_t b = 0; b < nv;) {
        const std::size_t e = std::min(nv, b + (kPositionsGrain - in_task));
        pieces.push_back({static_cast<std::uint32_t>(m), b, e, compare});
        in_task += e - b;
        b = e;
        if (in_task == kPositionsGrain) {
          tasks.push_back(pieces.size());
          in_task = 0;
        }
      }
    }
    if (tasks.back() != pieces.size()) tasks.push_back(pieces.size());
    if (pieces.empty()) return same_as != nullptr;
    std::atomic<bool> same{same_as != nullptr};
    std::atomic<std::uint32_t> first_bad{std::numeric_limits<std::uint32_t>::max()};  // mesh
    // a static mesh moved: its first vertex that differs (mesh in the high half)
    std::atomic<std::uint64_t> first_moved{std::numeric_limits<std::uint64_t>::max()};
    auto lower = [](auto& atom, auto value) {
      auto was = atom.load(std::memory_order_relaxed);
      while (value < was && !atom.compare_exchange_weak(was, value, std::memory_order_relaxed)) {
      }
    };
    auto piece = [&](const InputPiece& p) {
      const PositionsView& v = views[p.mesh];
      if (p.compare) {
        const Positions& own = meshes[p.mesh].vertices;
        for (std::size_t i = p.b; i < p.e; ++i)
          if (v.point(i) != own.point(i)) {
            lower(first_moved, std::uint64_t(p.mesh) << 32 | i);
            return;
          }
        return;
      }
      double* out = dst.data() + 3 * topo->vertex_offset(p.mesh);
      if (v.is_dense_double()) {
        std::memcpy(out + 3 * p.b, static_cast<const double*>(v.data()) + 3 * p.b, 3 * (p.e - p.b) * sizeof(double));
      } else {
        for (std::size_t i = p.b; i < p.e; ++i)
          for (int k = 0; k < 3; ++k) out[3 * i + k] = v(i, k);
      }
      // a float converts to an infinite double only when it is infinite itself
      if (!all_finite(out + 3 * p.b, 3 * (p.e - p.b))) lower(first_bad, p.mesh);
      const double* ref = same_as ? same_as->data() + 3 * topo->vertex_offset(p.mesh) : nullptr;
      if (ref && same.load(std::memory_order_relaxed) &&
          std::memcmp(out + 3 * p.b, ref + 3 * p.b, 3 * (p.e - p.b) * sizeof(double)) != 0)
        same.store(false, std::memory_order_relaxed);
    };
    in_arena([&] {
      detail::WorkSpanRecorder recorder;
      const detail::StageClock clock(ws ? &recorder : nullptr);
      detail::for_each_index(
          tasks.size() - 1,
          [&](std::size_t t) {
            for (std::size_t i = tasks[t]; i < tasks[t + 1]; ++i) piece(pieces[i]);
          },
          tbb::simple_partitioner());
      if (ws) *ws += clock.work_span(clock.seconds());
    });
    if (const std::uint64_t moved = first_moved.load(std::memory_order_relaxed);
        moved != std::numeric_limits<std::uint64_t>::max()) {
      const auto m = static_cast<std::size_t>(moved >> 32);
      validate_positions(views[m], meshes[m].num_vertices(), what(m));  // a coordinate that is not finite, named
      throw Error(what(m) + ": the mesh is static, but vertex " + std::to_string(moved & 0xffffffffu) +
                  " differs from its initial position (give an empty PositionsView, or the same positions)");
    }
    const std::uint32_t bad = first_bad.load(std::memory_order_relaxed);
    if (bad != std::numeric_limits<std::uint32_t>::max())
      validate_positions(views[bad], meshes[bad].num_vertices(), what(bad));  // throws, naming the first fault
    return same.load(std::memory_order_relaxed);
  }

  static Method checked(std::optional<Method> method, Method fallback) {
    const Method m = method.value_or(fallback);
    if (static_cast<unsigned>(m) > static_cast<unsigned>(Method::Fbd))
      throw Error("Scene: method " + std::to_string(static_cast<unsigned>(m)) +
                  " is not a Method (expected bruteforce, traverse, phc or fbd)");
    return m;
  }

  /// `continues`: the step starts where the last one ended (Stepper::step). `into` (nullptr:
  /// none): a result whose contact list's storage the step's result takes over (Stepper::step),
  /// left empty when the engine fails. `input`: take_in()'s work and span, for the stats.
  StepResult run(Method method, Clock::time_point t0, detail::StepKind kind, bool continues, StepResult* into,
                 const WorkSpan& input) {
    StepResult r;
    std::vector<Contact>* storage = into ? &into->contacts : nullptr;
    try {
      // Isolated: while this thread waits inside the step, it takes only the step's own tasks,
      // never an outer task of the host that might step this scene again.
      r = in_arena([&] {
        return dop ? dop->step(method, kind, continues, storage) : aabb->step(method, kind, continues, storage);
      });
    } catch (...) {
      // A failure inside the engine (out of memory): the front may be half built; forget it.
      if (dop) dop->invalidate_front();
      if (aabb) aabb->invalidate_front();
      if (into) *into = StepResult{};
      throw;
    }
    r.stats.ws_input = input;
    r.stats.t_total = std::chrono::duration<double>(Clock::now() - t0).count();
    return r;
  }
};

Scene::Scene(std::vector<TriMesh> meshes, SceneOptions options)
    : impl_(std::make_unique<Impl>(std::move(meshes), options)) {}
Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

StepResult Scene::Impl::full_step(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                                   std::optional<Method> method, StepResult* into) {
  const auto t0 = Clock::now();
  StepGuard guard(busy);
  const Method m = checked(method, options.method);
  WorkSpan input;
  WorkSpan* ws = options.work_span ? &input : nullptr;
  const bool continues = take_in(start, "step start", this->start(), &last_end, ws);
  take_in(end, "step end", this->end(), nullptr, ws);
  StepResult r = run(m, t0, detail::StepKind::Full, continues, into, input);
  std::swap(last_end.xyz(), this->end().xyz());  // end() is reloaded by every step
  return r;
}

StepResult Scene::Impl::advance(const std::vector<PositionsView>& next, std::optional<Method> method,
                                StepResult* into) {
  const auto t0 = Clock::now();
  StepGuard guard(busy);
  const Method m = checked(method, options.method);
  WorkSpan input;
  take_in(next, "advance", end(), nullptr, options.work_span ? &input : nullptr);
  std::swap(last_end.xyz(), start().xyz());
  StepResult r;
  try {
    r = run(m, t0, detail::StepKind::Full, true, into, input);  // it starts where the last step ended
  } catch (...) {
    std::swap(last_end.xyz(), start().xyz());  // the last end stays the last end
    throw;
  }
  std::swap(last_end.xyz(), end().xyz());
  return r;
}

StepResult Scene::step(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                       std::optional<Method> method) {
  return impl_->full_step(start, end, method, nullptr);
}

StepResult Scene::advance(const std::vector<PositionsView>& next, std::optional<Method> method) {
  return impl_->advance(next, method, nullptr);
}

void Scene::step(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end, StepResult& result,
                 std::optional<Method> method) {
  result = impl_->full_step(start, end, method, &result);
}

void Scene::advance(const std::vector<PositionsView>& next, StepResult& result, std::optional<Method> method) {
  result = impl_->advance(next, method, &result);
}

StepResult Scene::Impl::query(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                              detail::StepKind kind, StepStats* stats) {
  const auto t0 = Clock::now();
  StepGuard guard(busy);
  WorkSpan input;
  WorkSpan* ws = options.work_span ? &input : nullptr;
  take_in(start, "query start", this->start(), nullptr, ws);
  take_in(end, "query end", this->end(), nullptr, ws);
  StepResult r = run(options.method, t0, kind, false, nullptr, input);
  if (stats) *stats = r.stats;
  return r;
}

bool Scene::is_collision_free(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                              StepStats* stats) {
  return impl_->query(start, end, detail::StepKind::FirstContact, stats).contacts.empty();
}

double Scene::earliest_impact(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                              StepStats* stats) {
  return impl_->query(start, end, detail::StepKind::Earliest, stats).earliest_toi;
}

std::vector<Contact> Scene::candidates(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                                       StepStats* stats) {
  return impl_->query(start, end, detail::StepKind::Candidates, stats).contacts;
}

std::size_t Scene::num_meshes() const { return impl_->meshes.size(); }
const TriMesh& Scene::mesh(std::size_t i) const { return impl_->meshes.at(i); }
const MeshTopology& Scene::topology() const { return impl_->topo->topology(); }
std::size_t Scene::vertex_offset(std::size_t m) const { return impl_->topo->vertex_offset(m); }
std::size_t Scene::face_offset(std::size_t m) const { return impl_->topo->face_offset(m); }
std::size_t Scene::edge_offset(std::size_t m) const { return impl_->topo->edge_offset(m); }
std::size_t Scene::orphan_vf_count() const { return impl_->topo->orphans().vf().size(); }
std::size_t Scene::orphan_ee_count() const { return impl_->topo->orphans().ee().size(); }
std::size_t Scene::bvh_depth() const { return impl_->dop ? impl_->dop->bvh_depth() : impl_->aabb->bvh_depth(); }
const SceneOptions& Scene::options() const { return impl_->options; }

}  // namespace mccd
