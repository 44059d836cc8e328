#pragma once
/// @file Test support: a BVTT (core/bvtt.h) over a generated scene without the engine, and the
/// simple references the traversal tests compare against.
///  - BvttScene: a scene's BVH, and node volumes computed here for any step: each leaf's
///    quarter q holds its triangles' corners at the quarter's two ends, each inner node the
///    merge of its children (a plain recursive merge, not the library's refit);
///  - RecordingLeaf: the Bvtt's leaf-pair handler; it records each processed leaf pair, with
///    the quarters it was handed, as a RawContact (key: the two leaves; toi: the quarters);
///  - brute_force_pairs(): every leaf pair whose volumes overlap, over all pairs of leaves;
///  - is_cut(): whether a front is a cut of the BVTT: every leaf pair the traversal may
///    reach lies under exactly one front node.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/core/bvtt.h>
#include <mccd/core/query.h>
#include <mccd/core/scene_topology.h>
#include <mccd/core/worker_output.h>
#include <mccd/geometry/kdop.h>
#include <mccd/geometry/quarter_volumes.h>

#include "fixtures/scenes.h"

namespace mccd::test {

using NodeVolume = QuarterVolume<Kdop18>;

/// A processed leaf pair: the leaves (a < b) and the quarters handed to the leaf handler.
struct LeafPairHit {
  std::uint32_t a, b;
  unsigned quarters;
  friend auto operator<=>(const LeafPairHit&, const LeafPairHit&) = default;
};

inline std::string describe(const LeafPairHit& h) {
  std::string r = "(";
  r += std::to_string(h.a);
  r += ", ";
  r += std::to_string(h.b);
  r += ") q";
  r += std::to_string(h.quarters);
  return r;
}

/// The leaf-pair handler of the test BVTT: records what it is asked to process. With
/// `skip_mod`, leaf pairs with (a + b) % skip_mod == 0 are skipped without a test (as the
/// canonical rule skips leaf pairs of adjacent triangles).
struct RecordingLeaf {
  unsigned skip_mod = 0;
  /// Feature-pair tests each processed leaf pair counts, and pairs it queues (emptied by
  /// finish()): what the traversal's budget weighs a leaf pair by.
  std::uint64_t tested_per_pair = 0;
  std::size_t queued_per_pair = 0;
  bool skips(std::uint32_t a, std::uint32_t b) const { return skip_mod && (a + b) % skip_mod == 0; }
  void process(std::uint32_t a, std::uint32_t b, unsigned quarters, detail::WorkerOutput& out) const {
    detail::RawContact c{};
    c.key = detail::RawContact::make_key(ContactKind::VertexFace, a, b);
    c.toi = quarters;
    out.contacts.push_back(c);
    out.stats.feature_box_tests += tested_per_pair;
    for (std::size_t k = 0; k < queued_per_pair; ++k) out.queued.push_back(detail::QueuedPair{});
  }
  void finish(detail::WorkerOutput& out) const { out.queued.clear(); }
  unsigned touch(std::uint32_t, std::uint32_t) const { return 0; }
};

/// The hits recorded by RecordingLeaf in `contacts` (any range of RawContact), sorted;
/// duplicates kept.
template <class Range>
std::vector<LeafPairHit> hits(const Range& contacts) {
  std::vector<LeafPairHit> h;
  for (const detail::RawContact& c : contacts) h.push_back({c.a(), c.b(), static_cast<unsigned>(c.toi)});
  std::sort(h.begin(), h.end());
  return h;
}

inline Positions global_positions(const std::vector<Positions>& frame) {
  Positions x;
  for (const Positions& p : frame) x.xyz().insert(x.xyz().end(), p.xyz().begin(), p.xyz().end());
  return x;
}

class BvttScene {
 public:
  using Bvtt = detail::Bvtt<NodeVolume, RecordingLeaf>;

  /// The scene's BVH (built at frame 0, `leaf_size` triangles a leaf), its topology (mesh
  /// options `meshes`, empty: defaults) and the node volumes of step 0.
  BvttScene(const AnimatedScene& s, unsigned leaf_size, std::vector<MeshOptions> meshes = {},
            unsigned skip_mod = 0)
      : faces_(detail::scene_faces(s.meshes)) {
    for (const auto& f : s.frames) frames_.push_back(global_positions(f));
    topo_ = std::make_unique<detail::SceneTopology>(faces_, std::move(meshes), Representatives::Leaf);
    bvh_ = BvhTopology(triangle_bounds(faces_.faces, frames_[0]), BvhBuild::Sah, leaf_size, faces_.face_offsets,
                       &faces_.faces);
    nodes_.resize(bvh_.size());
    leaf_.skip_mod = skip_mod;
    query_.reset(detail::StepKind::Full);
    bvtt_ = std::make_unique<Bvtt>(bvh_, nodes_, *topo_, leaf_, query_);
    for (std::uint32_t n = 0; n < bvh_.size(); ++n)
      if (bvh_.leaf(n)) leaf_index_.emplace_back(n);
    set_step(0);
  }

  std::size_t steps() const { return frames_.size() - 1; }
  const BvhTopology& bvh() const { return bvh_; }
  const Bvtt& bvtt() const { return *bvtt_; }
  const detail::SceneTopology& topology() const { return *topo_; }
  detail::LargeVector<NodeVolume>& nodes() { return nodes_; }
  const std::vector<std::uint32_t>& leaves() const { return leaf_index_; }

  /// Leaf `n`'s quarter volumes over step f (frames f -> f + 1).
  NodeVolume leaf_volume(std::uint32_t n, std::size_t f) const {
    const Positions &x0 = frames_[f], &x1 = frames_[f + 1];
    NodeVolume v = NodeVolume::empty();
    for (int q = 0; q < 4; ++q) {
      Kdop18 d = Kdop18::empty();
      for (std::uint32_t k = 0; k < bvh_.leaf_count(n); ++k)
        for (std::uint32_t c : faces_.faces[bvh_.leaf_triangles(n)[k]]) {
          const Vec3 p0 = x0.point(c), p1 = x1.point(c);
          d.add_point(p0 + (p1 - p0) * (0.25 * q));
          d.add_point(p0 + (p1 - p0) * (0.25 * (q + 1)));
        }
      v.set(q, d);
    }
    return v;
  }

  /// Every node volume for step f: leaves from leaf_volume(), inner nodes merged from their
  /// children, recursively.
  void set_step(std::size_t f) {
    step_ = f;
    if (bvh_.size()) merge_below(0, f, nodes_);
  }
  std::size_t step() const { return step_; }

  /// The reference volumes of step f into `out` (resized): the same recursive merge.
  void reference_volumes(std::size_t f, detail::LargeVector<NodeVolume>& out) const {
    out.resize(bvh_.size());
    if (bvh_.size()) merge_below(0, f, out);
  }

  /// Whether the traversal never tests leaf pair (a, b) at all (skipped by the leaf
  /// handler, or between meshes whose pairs the scene never tests).
  bool never_tested(std::uint32_t a, std::uint32_t b) const {
    if (leaf_.skips(a, b)) return true;
    if (!topo_->has_skipped_pairs()) return false;
    return topo_->skips(bvh_.mesh_of_node(a), bvh_.mesh_of_node(b));
  }

  /// The reference: every pair of distinct leaves (a < b) the traversal tests, whose volumes
  /// overlap in some quarter, with those quarters; over all pairs of leaves.
  std::vector<LeafPairHit> brute_force_pairs() const {
    std::vector<LeafPairHit> r;
    for (std::size_t i = 0; i < leaf_index_.size(); ++i)
      for (std::size_t j = i + 1; j < leaf_index_.size(); ++j) {
        const std::uint32_t a = leaf_index_[i], b = leaf_index_[j];
        if (never_tested(a, b)) continue;
        if (const unsigned q = nodes_[a].overlap_mask(nodes_[b])) r.push_back({a, b, q});
      }
    return r;
  }

  /// Whether `front` is a cut of the BVTT for the traversal: pair nodes only (a < b < size,
  /// disjoint subtrees), every leaf pair the traversal tests under exactly one of them, no
  /// leaf pair under two, and no never-tested leaf pair as a node of its own. With
  /// `stops_now`, also that every node is where a traversal with the current volumes stops:
  /// a leaf pair, or a pair whose volumes do not overlap.
  ::testing::AssertionResult is_cut(const std::vector<detail::NodePair>& front, bool stops_now) const {
    const std::size_t L = leaf_index_.size();
    std::vector<std::uint32_t> dense(bvh_.size(), ~0u);
    for (std::size_t i = 0; i < L; ++i) dense[leaf_index_[i]] = static_cast<std::uint32_t>(i);
    std::vector<std::uint8_t> covered(L * L, 0);
    auto leaves_under = [&](std::uint32_t n) {
      std::vector<std::uint32_t> r;
      for (std::uint32_t i = n; i < bvh_.nodes()[n].end; ++i)
        if (bvh_.leaf(i)) r.push_back(dense[i]);
      return r;
    };
    for (const detail::NodePair& p : front) {
      const std::string node = "front node (" + std::to_string(p.a) + ", " + std::to_string(p.b) + ")";
      if (!(p.a < p.b && p.b < bvh_.size())) return ::testing::AssertionFailure() << node << " out of range";
      if (p.b < bvh_.nodes()[p.a].end) return ::testing::AssertionFailure() << node << ": nested subtrees";
      const bool leaf_pair = bvh_.leaf(p.a) && bvh_.leaf(p.b);
      if (leaf_pair && never_tested(p.a, p.b)) return ::testing::AssertionFailure() << node << " is never tested";
      if (stops_now && !leaf_pair && nodes_[p.a].overlap_mask(nodes_[p.b]))
        return ::testing::AssertionFailure() << node << ": inner, and its volumes overlap";
      for (std::uint32_t i : leaves_under(p.a))
        for (std::uint32_t j : leaves_under(p.b)) {
          const std::size_t k = std::min(i, j) * L + std::max(i, j);
          if (++covered[k] > 1)
            return ::testing::AssertionFailure() << "leaf pair (" << leaf_index_[std::min(i, j)] << ", "
                                                 << leaf_index_[std::max(i, j)] << ") under two front nodes, one "
                                                 << node;
        }
    }
    for (std::size_t i = 0; i < L; ++i)
      for (std::size_t j = i + 1; j < L; ++j)
        if (!covered[i * L + j] && !never_tested(leaf_index_[i], leaf_index_[j]))
          return ::testing::AssertionFailure() << "leaf pair (" << leaf_index_[i] << ", " << leaf_index_[j]
                                               << ") under no front node";
    return ::testing::AssertionSuccess();
  }

 private:
  void merge_below(std::uint32_t n, std::size_t f, detail::LargeVector<NodeVolume>& out) const {
    if (bvh_.leaf(n)) {
      out[n] = leaf_volume(n, f);
      return;
    }
    merge_below(bvh_.left(n), f, out);
    merge_below(bvh_.right(n), f, out);
    NodeVolume v = out[bvh_.left(n)];
    v.merge(out[bvh_.right(n)]);
    out[n] = v;
  }

  detail::SceneFaces faces_;
  std::vector<Positions> frames_;
  std::unique_ptr<detail::SceneTopology> topo_;
  BvhTopology bvh_;
  detail::LargeVector<NodeVolume> nodes_;
  RecordingLeaf leaf_;
  detail::QueryState query_;
  std::unique_ptr<Bvtt> bvtt_;
  std::vector<std::uint32_t> leaf_index_;
  std::size_t step_ = 0;
};

/// Whether two volumes are the same, bit for bit.
inline bool same_volume(const NodeVolume& a, const NodeVolume& b) {
  return std::memcmp(a.bounds, b.bounds, sizeof a.bounds) == 0;
}

inline std::vector<detail::NodePair> sorted(std::vector<detail::NodePair> v) {
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace mccd::test
