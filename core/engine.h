#pragma once
/// @file The per-step machinery behind Scene, templated on the bounding volume: vertex
/// volumes, BVH refit, the three methods (brute force, traversal from the root, front
/// tracking), leaf-pair processing with representative features, and orphan tests.
///
/// Consistency invariant that makes all methods return identical contacts: every feature
/// pair reaches the elementary test only after the overlap test of its *feature volumes*
/// (merges of the same per-vertex swept volumes that build the triangle and node volumes).
/// A feature volume is contained in the volume of every triangle around the feature and of
/// every BVH node above it, so whenever the feature test passes, every carrier pair and all
/// its ancestors overlap and every method reaches the pair.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <vector>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/concurrent_vector.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>

#include "core/bvh.h"
#include "core/contact.h"
#include "core/features.h"
#include "geometry/ccd.h"
#include "geometry/kdop.h"

namespace mccd::detail {

/// A BVTT pair node: two BVH node ids, a < b (a == b would be a self node).
struct NodePair {
  std::uint32_t a, b;  ///< 8 bytes
  friend bool operator<(const NodePair& x, const NodePair& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; }
};
static_assert(sizeof(NodePair) == 8);

/// A contact as found, with global ids (VF: vertex, face; EE: edge a < edge b).
struct RawContact {
  std::uint32_t a, b;
  ContactKind kind;
  double toi;
};

/// Counters of one worker (one block of the front, or one serial pass).
struct Counters {
  std::uint64_t volume_tests = 0, feature_box_tests = 0, vf_tests = 0, ee_tests = 0, leaf_pairs = 0,
                sprouted = 0, invalidated = 0, orphan_vf = 0, orphan_ee = 0, adjacent_leaf_pairs = 0;
  CcdCounters vf_ccd, ee_ccd;  ///< per-stage counts inside the elementary tests
  void add(const Counters& o) {
    vf_ccd.root_tests += o.vf_ccd.root_tests;
    ee_ccd.root_tests += o.ee_ccd.root_tests;
    volume_tests += o.volume_tests;
    feature_box_tests += o.feature_box_tests;
    vf_tests += o.vf_tests;
    ee_tests += o.ee_tests;
    leaf_pairs += o.leaf_pairs;
    adjacent_leaf_pairs += o.adjacent_leaf_pairs;
    sprouted += o.sprouted;
    invalidated += o.invalidated;
    orphan_vf += o.orphan_vf;
    orphan_ee += o.orphan_ee;
  }
};

/// The step's contacts, fed by the workers in batches (one per block or task); their order
/// depends on scheduling until the step sorts them.
using ContactBuffer = tbb::concurrent_vector<RawContact>;

/// Output of one unit of work: its part of the next front, its contacts, its counters, and
/// its traversal stack (kept to reuse the allocation).
struct WorkerOutput {
  std::vector<NodePair> front;
  std::vector<RawContact> contacts;
  std::vector<NodePair> stack;
  Counters counters;
  /// Moves this worker's contacts into the shared buffer as one batch.
  void flush(ContactBuffer& buffer) {
    if (!contacts.empty()) buffer.grow_by(contacts.begin(), contacts.end());
    contacts.clear();
  }
  void clear() {
    front.clear();
    contacts.clear();
    stack.clear();
    counters = {};
  }
};

/// The static data of a scene, independent of the volume type.
struct SceneGeometry {
  MeshTopology topo;
  FeaturePairs features;
  const Positions* x0 = nullptr;  ///< start positions of the step (global vertex ids)
  const Positions* x1 = nullptr;  ///< end positions
  CcdOptions ccd;
};

template <class BV>
class Engine {
 public:
  Engine(SceneGeometry& g, const std::vector<Vec3>& centroids) : g_(g), bvh_(centroids) {
    volumes_.resize(bvh_.size());
    vertex_volumes_.resize(g_.topo.num_vertices());
    edge_volumes_.resize(g_.topo.num_edges());
    piece_volumes_.resize(g_.topo.num_vertices());
    face_piece_volumes_.resize(g_.topo.num_faces());
    plan_refit();
  }

  const BvhTopology& bvh() const { return bvh_; }

  /// Stage 1 (second half): per-vertex swept volumes of the current step.
  void update_vertex_volumes() {
    const Positions& x0 = *g_.x0;
    const Positions& x1 = *g_.x1;
    // Fixed-size work per item: a static partition over the cores.
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, vertex_volumes_.size(), 4096),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t v = r.begin(); v != r.end(); ++v) {
            BV d = BV::empty();
            d.add_point(x0.row(static_cast<Eigen::Index>(v)).transpose());
            d.add_point(x1.row(static_cast<Eigen::Index>(v)).transpose());
            if (g_.ccd.min_distance > 0) d.inflate(g_.ccd.min_distance);
            vertex_volumes_[v] = d;
            // Pieces of the path, between computed points x0 + (k/4) (x1 - x0). Those points
            // and their projections carry rounding errors relative to the coordinates (not
            // to the projections), so each piece is inflated by 2^-48 of the largest
            // coordinate, far above those errors, on top of the outward float rounding.
            const Vec3 a = x0.row(static_cast<Eigen::Index>(v)).transpose();
            const Vec3 b = x1.row(static_cast<Eigen::Index>(v)).transpose();
            const Vec3 step = b - a;
            const Vec3 pts[5] = {a, a + 0.25 * step, a + 0.5 * step, a + 0.75 * step, b};
            const double margin = std::ldexp(std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()), -48) +
                                  g_.ccd.min_distance;
            auto piece = [&](int from, int to) {
              BV h = BV::empty();
              for (int k = from; k <= to; ++k) h.add_point(pts[k]);
              h.inflate(margin);
              return h;
            };
            piece_volumes_[v][0] = piece(0, 2);
            piece_volumes_[v][1] = piece(2, 4);
            for (int k = 0; k < 4; ++k) piece_volumes_[v][2 + k] = piece(k, k + 1);
          }
        },
        tbb::static_partitioner());
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, g_.topo.num_faces(), 4096),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t f = r.begin(); f != r.end(); ++f) {
            const Triangle& t = g_.topo.faces()[f];
            for (int k = 0; k < 6; ++k) {
              BV d = BV::merged(piece_volumes_[t[0]][k], piece_volumes_[t[1]][k]);
              d.merge(piece_volumes_[t[2]][k]);
              face_piece_volumes_[f][k] = d;
            }
          }
        },
        tbb::static_partitioner());
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, edge_volumes_.size(), 4096),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t e = r.begin(); e != r.end(); ++e) {
            const Edge& ed = g_.topo.edges()[e];
            edge_volumes_[e] = BV::merged(vertex_volumes_[ed[0]], vertex_volumes_[ed[1]]);
          }
        },
        tbb::static_partitioner());
  }

  /// Stage 2: refit every node volume bottom-up (paper section 4.7). The BVH never changes
  /// shape, so its split into subtrees of similar size is computed once: the subtrees are
  /// refitted under a static partition, then the few nodes above them serially.
  void refit() {
    if (bvh_.size() == 0) return;
    auto leaf = [this](std::uint32_t t) { return triangle_volume(t); };
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, refit_roots_.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const std::uint32_t root = refit_roots_[i];
            refit_range(bvh_, volumes_, root, bvh_.nodes()[root].end, leaf);
          }
        },
        tbb::static_partitioner());
    // the top: nodes above the cut, deepest first (reverse depth-first order)
    for (auto it = refit_top_.rbegin(); it != refit_top_.rend(); ++it)
      volumes_[*it] = BV::merged(volumes_[bvh_.left(*it)], volumes_[bvh_.right(*it)]);
  }

  BV triangle_volume(std::uint32_t t) const {
    const Triangle& f = g_.topo.faces()[t];
    BV d = BV::merged(vertex_volumes_[f[0]], vertex_volumes_[f[1]]);
    d.merge(vertex_volumes_[f[2]]);
    return d;
  }
  const BV& edge_volume(std::uint32_t e) const { return edge_volumes_[e]; }

  // ---- elementary tests behind the feature-volume test ----
  void test_vf(std::uint32_t v, std::uint32_t f, WorkerOutput& out) const {
    ++out.counters.feature_box_tests;
    if (!vertex_volumes_[v].overlaps(volumes_[bvh_.leaf_of(f)])) return;
    const Triangle& t = g_.topo.faces()[f];
    if (!vertex_face_pieces_overlap(v, f)) return;
    ++out.counters.vf_tests;
    CcdPoints p;
    const std::uint32_t ids[4] = {v, t[0], t[1], t[2]};
    load(ids, p);
    double toi = 0;
    if (vertex_face_ccd(p, toi, g_.ccd, &out.counters.vf_ccd)) out.contacts.push_back({v, f, ContactKind::VertexFace, toi});
  }
  void test_ee(std::uint32_t a, std::uint32_t b, WorkerOutput& out) const {
    if (a > b) std::swap(a, b);
    ++out.counters.feature_box_tests;
    if (!edge_volume(a).overlaps(edge_volume(b))) return;
    const Edge& ea = g_.topo.edges()[a];
    const Edge& eb = g_.topo.edges()[b];
    if (!edge_pieces_overlap(ea, eb)) return;
    ++out.counters.ee_tests;
    CcdPoints p;
    const std::uint32_t ids[4] = {ea[0], ea[1], eb[0], eb[1]};
    load(ids, p);
    double toi = 0;
    if (edge_edge_ccd(p, toi, g_.ccd, &out.counters.ee_ccd)) out.contacts.push_back({a, b, ContactKind::EdgeEdge, toi});
  }

  /// Time-split tests: whether two features (or two triangles) may meet in one piece of the
  /// step. A contact at time t lies in both features' volumes of every piece holding t (a
  /// half, then a quarter of it). Only consulted after the whole-step volumes overlap, so a
  /// pair passing them still passes every coarser test above it (the consistency invariant of
  /// this file).
  bool edge_pieces_overlap(const Edge& ea, const Edge& eb) const {
    const auto &a0 = piece_volumes_[ea[0]], &a1 = piece_volumes_[ea[1]];
    const auto &b0 = piece_volumes_[eb[0]], &b1 = piece_volumes_[eb[1]];
    auto overlap = [&](int k) { return BV::merged(a0[k], a1[k]).overlaps(BV::merged(b0[k], b1[k])); };
    for (int h = 0; h < 2; ++h)
      if (overlap(h) && (overlap(2 + 2 * h) || overlap(3 + 2 * h))) return true;
    return false;
  }

  bool vertex_face_pieces_overlap(std::uint32_t v, std::uint32_t f) const {
    auto overlap = [&](int k) { return piece_volumes_[v][k].overlaps(face_piece_volumes_[f][k]); };
    for (int h = 0; h < 2; ++h)
      if (overlap(h) && (overlap(2 + 2 * h) || overlap(3 + 2 * h))) return true;
    return false;
  }

  bool faces_overlap_in_pieces(std::uint32_t s, std::uint32_t t) const {
    auto overlap = [&](int k) { return face_piece_volumes_[s][k].overlaps(face_piece_volumes_[t][k]); };
    for (int h = 0; h < 2; ++h)
      if (overlap(h) && (overlap(2 + 2 * h) || overlap(3 + 2 * h))) return true;
    return false;
  }

  /// The feature pairs carried by the non-adjacent, overlapping leaf pair (s, t).
  void process_leaf_pair(std::uint32_t s, std::uint32_t t, WorkerOutput& out) const {
    ++out.counters.leaf_pairs;
    const Triangle& S = g_.topo.faces()[s];
    const Triangle& T = g_.topo.faces()[t];
    // Every feature of s and t lies in its triangle during each piece of the step: when the
    // triangles' piece volumes never meet, no feature pair below can pass its own test.
    if (!faces_overlap_in_pieces(s, t)) return;
    for (auto v : S)
      if (g_.features.carries_vf(v, s, t)) test_vf(v, t, out);
    for (auto v : T)
      if (g_.features.carries_vf(v, t, s)) test_vf(v, s, out);
    const auto& es = g_.topo.face_edges(s);
    const auto& et = g_.topo.face_edges(t);
    for (auto a : es)
      for (auto b : et)
        if (g_.features.carries_ee(a, s, b, t)) test_ee(a, b, out);
  }

  /// Depth-first BVTT traversal of everything on out.stack. With `record`, the pair nodes
  /// where it stops (disjoint pairs, non-adjacent leaf pairs) are appended to out.front.
  /// Adjacent leaf pairs stop without a volume test: their features are the orphan set's.
  template <bool record>
  void traverse(WorkerOutput& out) const {
    auto& st = out.stack;
    while (!st.empty()) {
      const NodePair n = st.back();
      st.pop_back();
      visit<record>(n, out, st);
    }
  }

  /// One BVTT node: a self node yields its three children; a pair node is tested and either
  /// stops (recorded in the front with `record`) or yields its two children into `next`.
  template <bool record>
  void visit(const NodePair n, WorkerOutput& out, std::vector<NodePair>& next) const {
    if (n.a == n.b) {  // self node: three children, no test
      if (bvh_.leaf(n.a)) return;
      const std::uint32_t l = bvh_.left(n.a), r = bvh_.right(n.a);
      next.push_back({l, r});
      next.push_back({r, r});
      next.push_back({l, l});
      return;
    }
    if (bvh_.leaf(n.a) && bvh_.leaf(n.b)) {
      const std::uint32_t s = bvh_.triangle(n.a), t = bvh_.triangle(n.b);
      if (g_.topo.adjacent(s, t)) {
        ++out.counters.adjacent_leaf_pairs;
        return;
      }
      if constexpr (record) out.front.push_back(n);
      ++out.counters.volume_tests;
      if (volumes_[n.a].overlaps(volumes_[n.b])) process_leaf_pair(s, t, out);
      return;
    }
    ++out.counters.volume_tests;
    if (!volumes_[n.a].overlaps(volumes_[n.b])) {
      if constexpr (record) out.front.push_back(n);
      return;
    }
    push_children(n, next);
  }

  /// Children of an inner pair node: split the non-leaf, or the larger, of the two.
  void push_children(const NodePair& n, std::vector<NodePair>& st) const {
    const bool split_b = bvh_.leaf(n.a) || (!bvh_.leaf(n.b) && bvh_.subtree_size(n.b) > bvh_.subtree_size(n.a));
    if (split_b) {
      st.push_back({n.a, bvh_.right(n.b)});
      st.push_back({n.a, bvh_.left(n.b)});
    } else {
      st.push_back({bvh_.right(n.a), n.b});
      st.push_back({bvh_.left(n.a), n.b});
    }
  }

  /// Traversal from the root (the `traverse` method; with `record`, the front build of
  /// paper algorithms 3-4), in parallel. The top of the BVTT is visited breadth-first, round
  /// by round, until at least `min_tasks` nodes wait (or none); each waiting node's subtree
  /// is then traversed depth-first as one task into outs[1 + i], the top's own work going to
  /// outs[0]. The split depends only on the geometry, never on the thread count, and every
  /// node is visited exactly as in a serial traversal: the same tests, stops and contacts.
  template <bool record>
  void from_root(std::vector<WorkerOutput>& outs, ContactBuffer& contacts, std::size_t min_tasks = 256) const {
    if (outs.empty()) outs.resize(1);
    outs[0].clear();
    if (bvh_.size() == 0) {
      outs.resize(1);
      return;
    }
    std::vector<NodePair> tasks{{0, 0}}, next;
    while (!tasks.empty() && tasks.size() < min_tasks) {
      next.clear();
      for (const NodePair& n : tasks) visit<record>(n, outs[0], next);
      tasks.swap(next);
    }
    outs.resize(1 + tasks.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tasks.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        WorkerOutput& o = outs[1 + i];
        o.clear();
        o.stack.push_back(tasks[i]);
        traverse<record>(o);
        o.flush(contacts);
      }
    });
  }

  /// Front tracking of nodes [begin, end) (paper section 4.3-4.4): a disjoint node stays; an
  /// overlapping leaf pair is processed and stays; an overlapping inner node is replaced by
  /// the stops of its subtree (sprouting, no pruning).
  void track(const NodePair* begin, const NodePair* end, WorkerOutput& out) const {
    for (const NodePair* it = begin; it != end; ++it) {
      const NodePair n = *it;
      ++out.counters.volume_tests;
      const bool ov = volumes_[n.a].overlaps(volumes_[n.b]);
      if (bvh_.leaf(n.a) && bvh_.leaf(n.b)) {
        if (ov) process_leaf_pair(bvh_.triangle(n.a), bvh_.triangle(n.b), out);
        out.front.push_back(n);
      } else if (!ov) {
        out.front.push_back(n);
      } else {
        ++out.counters.invalidated;
        const std::size_t before = out.front.size();
        push_children(n, out.stack);
        traverse<true>(out);
        out.counters.sprouted += out.front.size() - before;
      }
    }
  }

  /// The orphan set (paper section 4.6): every orphan pair behind its feature-volume tests.
  void orphans(WorkerOutput& out) const {
    for (const auto& [v, f] : g_.features.orphan_vf()) test_vf(v, f, out);
    for (const auto& [a, b] : g_.features.orphan_ee()) test_ee(a, b, out);
  }

  /// Brute force: every VF pair (v not a corner of f) and every EE pair sharing no vertex,
  /// found by sweep and prune on slab 0 of the feature volumes, then the same feature
  /// volume test and elementary tests as the other methods.
  void brute_force(WorkerOutput& out) const {
    const auto& topo = g_.topo;
    // sweep along the slab where the scene is widest (fewest overlapping intervals)
    int ax = 0;
    if (bvh_.size() > 0) {
      float best = -1;
      for (int k = 0; k < 3; ++k)
        if (volumes_[0].hi[k] - volumes_[0].lo[k] > best) best = volumes_[0].hi[k] - volumes_[0].lo[k], ax = k;
    }
    // VF: faces sorted by lower bound; each vertex scans the faces whose interval can reach it.
    std::vector<std::pair<double, std::uint32_t>> faces(topo.num_faces());
    double max_face_extent = 0;  // the widest face along the sweep axis
    for (std::uint32_t f = 0; f < faces.size(); ++f) {
      const BV& vf = volumes_[bvh_.leaf_of(f)];
      faces[f] = {vf.lo[ax], f};
      max_face_extent = std::max(max_face_extent, double(vf.hi[ax]) - double(vf.lo[ax]));
    }
    std::sort(faces.begin(), faces.end());
    for (std::uint32_t v = 0; v < topo.num_vertices(); ++v) {
      if (topo.vertex_face_count(v) == 0) continue;
      const BV& vv = vertex_volumes_[v];
      // A face reaching the vertex has lo <= vv.hi and lo >= vv.lo - extent; the margin only
      // widens the scan (the full volume test decides).
      const double key = double(vv.lo[ax]) - max_face_extent * (1 + 1e-6) - 1e-30;
      auto it = std::lower_bound(faces.begin(), faces.end(), std::make_pair(key, 0u));
      for (; it != faces.end() && it->first <= double(vv.hi[ax]); ++it) {
        const std::uint32_t f = it->second;
        const Triangle& t = topo.faces()[f];
        if (t[0] == v || t[1] == v || t[2] == v) continue;
        ++out.counters.volume_tests;
        if (!vv.overlaps(volumes_[bvh_.leaf_of(f)])) continue;
        test_vf(v, f, out);
      }
    }
    // EE: classic sweep over edges sorted by lower bound.
    std::vector<std::pair<float, std::uint32_t>> edges(topo.num_edges());
    const std::vector<BV>& ev = edge_volumes_;
    for (std::uint32_t e = 0; e < edges.size(); ++e) edges[e] = {ev[e].lo[ax], e};
    std::sort(edges.begin(), edges.end());
    for (std::size_t i = 0; i < edges.size(); ++i) {
      const std::uint32_t a = edges[i].second;
      const Edge& ea = topo.edges()[a];
      for (std::size_t j = i + 1; j < edges.size() && edges[j].first <= ev[a].hi[ax]; ++j) {
        const std::uint32_t b = edges[j].second;
        const Edge& eb = topo.edges()[b];
        if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
        ++out.counters.volume_tests;
        if (!ev[a].overlaps(ev[b])) continue;
        test_ee(a, b, out);
      }
    }
  }

 private:
  /// Cuts the BVH into subtrees of at most ~1/64 of the nodes (and at least 2048 nodes, so
  /// small scenes stay one piece): refit_roots_ are their roots, refit_top_ the inner nodes
  /// above them in depth-first order.
  void plan_refit() {
    if (bvh_.size() == 0) return;
    const std::uint32_t limit = std::max<std::uint32_t>(2048, static_cast<std::uint32_t>(bvh_.size() / 64));
    std::vector<std::uint32_t> stack{0};
    while (!stack.empty()) {
      const std::uint32_t n = stack.back();
      stack.pop_back();
      if (bvh_.subtree_size(n) <= limit || bvh_.leaf(n)) {
        refit_roots_.push_back(n);
      } else {
        refit_top_.push_back(n);
        stack.push_back(bvh_.right(n));
        stack.push_back(bvh_.left(n));
      }
    }
    std::sort(refit_top_.begin(), refit_top_.end());  // depth-first order: parents first
  }

  void load(const std::uint32_t (&ids)[4], CcdPoints& p) const {
    for (int k = 0; k < 4; ++k) {
      p.start[k] = g_.x0->row(ids[k]).transpose();
      p.end[k] = g_.x1->row(ids[k]).transpose();
    }
  }

  SceneGeometry& g_;
  BvhTopology bvh_;
  std::vector<BV> volumes_;         ///< one per BVH node
  std::vector<BV> vertex_volumes_;  ///< one per vertex: its swept segment
  std::vector<BV> edge_volumes_;    ///< one per edge: merge of its two vertex volumes
  /// Per vertex, its path over the pieces of the step: [0, 1/2], [1/2, 1] (pieces 0, 1),
  /// then the quarters [k/4, (k+1)/4] (pieces 2..5).
  std::vector<std::array<BV, 6>> piece_volumes_;
  std::vector<std::array<BV, 6>> face_piece_volumes_;  ///< per face: merge of its vertices' pieces
  std::vector<std::uint32_t> refit_roots_;  ///< subtrees refitted in parallel
  std::vector<std::uint32_t> refit_top_;    ///< inner nodes above them, ascending
};

}  // namespace mccd::detail
