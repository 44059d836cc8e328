#include "core/scene.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "core/engine.h"
#include "geometry/error.h"

namespace mccd {

const char* to_string(Method m) {
  switch (m) {
    case Method::BruteForce: return "bruteforce";
    case Method::Traverse: return "traverse";
    case Method::Front: return "front";
  }
  return "?";
}

Method parse_method(const char* name) {
  if (!std::strcmp(name, "bruteforce")) return Method::BruteForce;
  if (!std::strcmp(name, "traverse")) return Method::Traverse;
  if (!std::strcmp(name, "front")) return Method::Front;
  throw Error(std::string("unknown method '") + name + "' (expected bruteforce, traverse or front)");
}

using detail::Counters;
using detail::NodePair;
using detail::RawContact;
using detail::WorkerOutput;

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
constexpr std::size_t kFrontBlock = 2048;  // front nodes per block of work
}  // namespace

/// Counting sort of front nodes by their first BVH node (stable: the traversal order is kept
/// among nodes of one first node). Linear in the front and the BVH size.
void sort_by_first_node(const std::vector<NodePair>& in, std::vector<NodePair>& out) {
  std::uint32_t max_a = 0;
  for (const NodePair& n : in) max_a = std::max(max_a, n.a);
  std::vector<std::uint32_t> start(std::size_t(max_a) + 2, 0);
  for (const NodePair& n : in) ++start[n.a + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  out.resize(in.size());
  for (const NodePair& n : in) out[start[n.a]++] = n;
}

struct Scene::Impl {
  SceneOptions options;
  std::vector<TriMesh> meshes;
  std::vector<std::size_t> vertex_offsets{0}, face_offsets{0}, edge_offsets{0};
  detail::SceneGeometry geo;
  Positions x0, x1;  // the step's start and end, global vertex ids
  std::unique_ptr<detail::Engine<Kdop18>> dop;
  std::unique_ptr<detail::Engine<Aabb>> aabb;

  // front state (paper section 4.5)
  std::vector<NodePair> front, next_front;
  std::uint64_t sprouted_since_build = 0, invalidated_since_build = 0;
  bool front_valid = false;
  std::vector<WorkerOutput> outputs;       // one per front block
  std::vector<WorkerOutput> root_outputs;  // one per task of a traversal from the root
  detail::ContactBuffer contact_buffer;    // the step's contacts, fed in batches by the workers

  Impl(std::vector<TriMesh> ms, SceneOptions opt) : options(opt), meshes(std::move(ms)) {
    if (!(options.min_distance >= 0) || !std::isfinite(options.min_distance))
      throw Error("scene options: min_distance must be finite and >= 0, got " + std::to_string(options.min_distance));
    if (!(options.rebuild_sprout_ratio > 0) || !(options.rebuild_invalid_ratio > 0))
      throw Error("scene options: rebuild ratios must be > 0");
    std::vector<Triangle> faces;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      if (meshes[m].name.empty()) meshes[m].name = "mesh " + std::to_string(m);
      validate_mesh(meshes[m]);
      const auto off = static_cast<std::uint32_t>(vertex_offsets.back());
      for (const Triangle& t : meshes[m].faces) faces.push_back({t[0] + off, t[1] + off, t[2] + off});
      vertex_offsets.push_back(vertex_offsets.back() + meshes[m].num_vertices());
      face_offsets.push_back(faces.size());
    }
    if (vertex_offsets.back() >= std::size_t(1) << 31 || faces.size() >= std::size_t(1) << 30)
      throw Error("scene: too many vertices or triangles for 32-bit ids");
    geo.topo = MeshTopology(vertex_offsets.back(), faces);
    // edges are sorted by (max, min) global vertex, so each mesh's edges are contiguous
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      std::size_t e = edge_offsets.back();
      while (e < geo.topo.num_edges() && geo.topo.edges()[e][1] < vertex_offsets[m + 1]) ++e;
      edge_offsets.push_back(e);
    }
    geo.features = FeaturePairs(geo.topo);
    geo.ccd.min_distance = options.min_distance;
    x1.resize(static_cast<Eigen::Index>(vertex_offsets.back()), 3);
    for (std::size_t m = 0; m < meshes.size(); ++m)
      x1.middleRows(static_cast<Eigen::Index>(vertex_offsets[m]), meshes[m].vertices.rows()) = meshes[m].vertices;
    x0 = x1;
    geo.x0 = &x0;
    geo.x1 = &x1;
    std::vector<Vec3> centroids(faces.size());
    for (std::size_t f = 0; f < faces.size(); ++f)
      centroids[f] = (x1.row(faces[f][0]) + x1.row(faces[f][1]) + x1.row(faces[f][2])).transpose() / 3.0;
    if (options.volume == VolumeKind::Kdop18)
      dop = std::make_unique<detail::Engine<Kdop18>>(geo, centroids);
    else
      aabb = std::make_unique<detail::Engine<Aabb>>(geo, centroids);
  }

  void check(const std::vector<PositionsView>& views, const char* which) const {
    if (views.size() != meshes.size())
      throw Error(std::string(which) + ": " + std::to_string(views.size()) + " position arrays for " +
                  std::to_string(meshes.size()) + " meshes");
    for (std::size_t m = 0; m < views.size(); ++m)
      validate_positions(views[m], meshes[m].num_vertices(),
                         std::string(which) + ", mesh " + std::to_string(m) + " (" + meshes[m].name + ")");
  }

  void load(const std::vector<PositionsView>& views, Positions& dst) const {
    for (std::size_t m = 0; m < views.size(); ++m)
      dst.middleRows(static_cast<Eigen::Index>(vertex_offsets[m]), views[m].rows()) = views[m];
  }

  template <class BV>
  StepResult run(detail::Engine<BV>& eng, Method method, Clock::time_point t_start) {
    StepResult res;
    StepStats& st = res.stats;
    st.method = method;
    auto t = Clock::now();
    eng.update_vertex_volumes();
    st.t_update = std::chrono::duration<double>(Clock::now() - t_start).count();
    t = Clock::now();
    eng.refit();
    st.t_refit = seconds_since(t);

    t = Clock::now();
    Counters total;
    contact_buffer.clear();
    auto collect = [&](WorkerOutput& o) {
      total.add(o.counters);
      o.flush(contact_buffer);  // what a serial part found
    };
    if (outputs.empty()) outputs.resize(1);
    if (method == Method::BruteForce) {
      outputs[0].clear();
      eng.brute_force(outputs[0]);
      collect(outputs[0]);
    } else if (method == Method::Traverse) {
      eng.template from_root<false>(root_outputs, contact_buffer);
      for (auto& o : root_outputs) collect(o);
    } else if (!front_valid) {
      eng.template from_root<true>(root_outputs, contact_buffer);
      std::size_t n = 0;
      for (auto& o : root_outputs) n += o.front.size();
      std::vector<NodePair> unsorted;
      unsorted.reserve(n);
      for (auto& o : root_outputs) {
        collect(o);
        unsorted.insert(unsorted.end(), o.front.begin(), o.front.end());
        o.front = std::vector<NodePair>();  // the pieces are not kept
      }
      sort_by_first_node(unsorted, front);  // BVH-node order (paper section 4.8)
      front_valid = true;
      sprouted_since_build = invalidated_since_build = 0;
      st.rebuilds = 1;
    } else {
      // Blocks of the front, each writing its own part of the next front and its own
      // contacts; concatenated in block order, so the result is independent of scheduling.
      const std::size_t blocks = (front.size() + kFrontBlock - 1) / kFrontBlock;
      if (outputs.size() < blocks) outputs.resize(blocks);
      // Blocks go to idle threads as they finish (work stealing); one block is the unit of
      // output, so the thread count only changes who computes a block, never its result.
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t b = r.begin(); b != r.end(); ++b) {
          WorkerOutput& o = outputs[b];
          o.clear();
          const std::size_t lo = b * kFrontBlock, hi = std::min(front.size(), lo + kFrontBlock);
          eng.track(front.data() + lo, front.data() + hi, o);
          o.flush(contact_buffer);
        }
      });
      next_front.clear();
      for (std::size_t b = 0; b < blocks; ++b) {
        collect(outputs[b]);
        next_front.insert(next_front.end(), outputs[b].front.begin(), outputs[b].front.end());
      }
      front.swap(next_front);
      sprouted_since_build += total.sprouted;
      invalidated_since_build += total.invalidated;
      const double L = static_cast<double>(std::max<std::size_t>(front.size(), 1));
      if (sprouted_since_build > options.rebuild_sprout_ratio * L ||
          invalidated_since_build > options.rebuild_invalid_ratio * L)
        front_valid = false;  // the next front step rebuilds from the root (equations 3-4)
    }
    st.t_front = seconds_since(t);

    t = Clock::now();
    if (method != Method::BruteForce) {
      WorkerOutput& o = outputs[0];
      o.clear();
      const Counters before = o.counters;
      eng.orphans(o);
      o.counters.orphan_vf = o.counters.vf_tests - before.vf_tests;
      o.counters.orphan_ee = o.counters.ee_tests - before.ee_tests;
      collect(o);
    }
    st.t_orphans = seconds_since(t);

    st.volume_tests = total.volume_tests;
    st.feature_box_tests = total.feature_box_tests;
    st.vf_tests = total.vf_tests;
    st.ee_tests = total.ee_tests;
    st.leaf_pairs = total.leaf_pairs;
    st.adjacent_leaf_pairs = total.adjacent_leaf_pairs;
    st.vf_root_tests = total.vf_ccd.root_tests;
    st.ee_root_tests = total.ee_ccd.root_tests;
    st.sprouted = total.sprouted;
    st.invalidated = total.invalidated;
    st.orphan_vf_tested = total.orphan_vf;
    st.orphan_ee_tested = total.orphan_ee;
    if (method == Method::Front) {
      st.front_size = front.size();
      st.front_bytes = (front.capacity() + next_front.capacity()) * sizeof(NodePair);
      for (auto& o : outputs) st.front_bytes += o.front.capacity() * sizeof(NodePair);
    }
    to_contacts(contact_buffer, res);
    st.t_total = seconds_since(t_start);
    return res;
  }

  static std::uint32_t mesh_of(std::size_t id, const std::vector<std::size_t>& offsets) {
    return static_cast<std::uint32_t>(std::upper_bound(offsets.begin(), offsets.end(), id) - offsets.begin() - 1);
  }

  void to_contacts(const detail::ContactBuffer& raw, StepResult& res) const {
    res.contacts.reserve(raw.size());
    for (const RawContact& r : raw) {
      Contact c{};
      c.kind = r.kind;
      c.toi = r.toi;
      if (r.kind == ContactKind::VertexFace) {
        c.mesh_a = mesh_of(r.a, vertex_offsets);
        c.a = static_cast<std::uint32_t>(r.a - vertex_offsets[c.mesh_a]);
        c.mesh_b = mesh_of(r.b, face_offsets);
        c.b = static_cast<std::uint32_t>(r.b - face_offsets[c.mesh_b]);
        ++res.stats.vf_contacts;
      } else {
        c.mesh_a = mesh_of(r.a, edge_offsets);
        c.a = static_cast<std::uint32_t>(r.a - edge_offsets[c.mesh_a]);
        c.mesh_b = mesh_of(r.b, edge_offsets);
        c.b = static_cast<std::uint32_t>(r.b - edge_offsets[c.mesh_b]);
        const Edge& ea = geo.topo.edges()[r.a];
        const Edge& eb = geo.topo.edges()[r.b];
        const auto va = static_cast<std::uint32_t>(vertex_offsets[c.mesh_a]);
        const auto vb = static_cast<std::uint32_t>(vertex_offsets[c.mesh_b]);
        c.a_vertices = {ea[0] - va, ea[1] - va};
        c.b_vertices = {eb[0] - vb, eb[1] - vb};
        ++res.stats.ee_contacts;
      }
      res.earliest_toi = std::min(res.earliest_toi, c.toi);
      res.contacts.push_back(c);
    }
    std::sort(res.contacts.begin(), res.contacts.end());
  }

  StepResult run(Method method, Clock::time_point t0) {
    auto body = [&] { return dop ? run(*dop, method, t0) : run(*aabb, method, t0); };
    if (options.arena) return options.arena->execute(body);
    return body();
  }
};

Scene::Scene(std::vector<TriMesh> meshes, SceneOptions options)
    : impl_(std::make_unique<Impl>(std::move(meshes), options)) {}
Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

StepResult Scene::step(const std::vector<PositionsView>& start, const std::vector<PositionsView>& end,
                       std::optional<Method> method) {
  const auto t0 = Clock::now();
  impl_->check(start, "step start");
  impl_->check(end, "step end");
  impl_->load(start, impl_->x0);
  impl_->load(end, impl_->x1);
  return impl_->run(method.value_or(impl_->options.method), t0);
}

StepResult Scene::advance(const std::vector<PositionsView>& next, std::optional<Method> method) {
  const auto t0 = Clock::now();
  impl_->check(next, "advance");
  impl_->x0.swap(impl_->x1);
  impl_->load(next, impl_->x1);
  return impl_->run(method.value_or(impl_->options.method), t0);
}

std::size_t Scene::num_meshes() const { return impl_->meshes.size(); }
const TriMesh& Scene::mesh(std::size_t i) const { return impl_->meshes.at(i); }
const MeshTopology& Scene::topology() const { return impl_->geo.topo; }
std::size_t Scene::vertex_offset(std::size_t m) const { return impl_->vertex_offsets.at(m); }
std::size_t Scene::face_offset(std::size_t m) const { return impl_->face_offsets.at(m); }
std::size_t Scene::edge_offset(std::size_t m) const { return impl_->edge_offsets.at(m); }
std::size_t Scene::orphan_vf_count() const { return impl_->geo.features.orphan_vf().size(); }
std::size_t Scene::orphan_ee_count() const { return impl_->geo.features.orphan_ee().size(); }
std::size_t Scene::bvh_depth() const {
  return impl_->dop ? impl_->dop->bvh().depth() : impl_->aabb->bvh().depth();
}
const SceneOptions& Scene::options() const { return impl_->options; }

}  // namespace mccd
