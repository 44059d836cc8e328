#include <mccd/core/bvh.h>

#include <mccd/geometry/disjoint_sets.h>
#include <mccd/geometry/large_allocator.h>

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>
#include <stdexcept>


namespace mccd {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Box {
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  void grow(const Box& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  double half_area() const {
    if (!(hi.x() >= lo.x())) return 0;
    const Vec3 d = hi - lo;
    return d.x() * d.y() + d.y() * d.z() + d.z() * d.x();
  }
};

class Builder {
 public:
  Builder(const std::vector<TriangleBounds>& tris, BvhBuild kind, unsigned max_leaf, std::vector<BvhNode>& nodes,
          std::vector<std::uint32_t>& order, std::vector<std::uint32_t>& node_mesh, const detail::Executor& ex)
      : tris_(tris), kind_(kind), max_leaf_(max_leaf), order_(order), nodes_(nodes), node_mesh_(node_mesh), ex_(ex) {
    order_.resize(tris.size());
    std::iota(order_.begin(), order_.end(), 0u);
  }
  std::uint32_t depth() const { return depth_; }

  /// The units `ids` (triangle ranges [offsets[u], offsets[u + 1]) of order_, each of one mesh,
  /// unit_mesh[u]): one subtree per unit under a top split at the median of the units'
  /// centroids along their widest axis. A node of the top whose units are all of one mesh is
  /// of that mesh, otherwise kMixed.
  std::uint32_t build_units(std::vector<std::uint32_t> ids, const std::vector<std::size_t>& offsets,
                            const std::vector<std::uint32_t>& unit_mesh, std::uint32_t level) {
    if (ids.size() == 1) {
      const std::uint32_t first = static_cast<std::uint32_t>(nodes_.size());
      const std::uint32_t root = build(offsets[ids[0]], offsets[ids[0] + 1], level);
      node_mesh_.resize(nodes_.size(), BvhTopology::kMixed);
      std::fill(node_mesh_.begin() + first, node_mesh_.end(), unit_mesh[ids[0]]);
      return root;
    }
    std::vector<Vec3> centre(ids.size());
    Vec3 mn = Vec3::Constant(kInf), mx = -mn;
    for (std::size_t k = 0; k < ids.size(); ++k) {
      Vec3 sum = Vec3::Zero();
      for (std::size_t t = offsets[ids[k]]; t < offsets[ids[k] + 1]; ++t) sum += tris_[order_[t]].centroid;
      centre[k] = sum / double(std::max<std::size_t>(1, offsets[ids[k] + 1] - offsets[ids[k]]));
      mn = mn.cwiseMin(centre[k]);
      mx = mx.cwiseMax(centre[k]);
    }
    int axis = 0;
    (mx - mn).maxCoeff(&axis);
    std::vector<std::size_t> by(ids.size());
    std::iota(by.begin(), by.end(), std::size_t(0));
    std::sort(by.begin(), by.end(), [&](std::size_t a, std::size_t b) {
      return centre[a][axis] != centre[b][axis] ? centre[a][axis] < centre[b][axis] : ids[a] < ids[b];
    });
    std::vector<std::uint32_t> left, right;
    for (std::size_t k = 0; k < by.size(); ++k) (k < by.size() / 2 ? left : right).push_back(ids[by[k]]);
    const auto index = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({0, 0});
    node_mesh_.resize(nodes_.size(), BvhTopology::kMixed);
    depth_ = std::max(depth_, level);
    build_units(std::move(left), offsets, unit_mesh, level + 1);
    const std::uint32_t r = build_units(std::move(right), offsets, unit_mesh, level + 1);
    nodes_[index] = {static_cast<std::uint32_t>(nodes_.size()), r};
    if (node_mesh_[index + 1] == node_mesh_[r]) node_mesh_[index] = node_mesh_[r];
    return index;
  }

  // Builds the subtree over order[lo, hi) at node index nodes.size(); returns its index.
  std::uint32_t build(std::size_t lo, std::size_t hi, std::uint32_t level) { return build(nodes_, lo, hi, level, depth_); }

 private:
  /// Ranges of at least this many triangles build their two halves in parallel (into their
  /// own arrays, spliced in order: the tree does not depend on the thread count).
  static constexpr std::size_t kParallelBuild = 8192;

  std::uint32_t build(std::vector<BvhNode>& out, std::size_t lo, std::size_t hi, std::uint32_t level,
                      std::uint32_t& depth) {
    const auto index = static_cast<std::uint32_t>(out.size());
    out.push_back({0, 0});
    depth = std::max(depth, level);
    if (hi - lo <= max_leaf_) {
      out[index] = {index + 1, static_cast<std::uint32_t>(lo << 5 | (hi - lo - 1))};
      return index;
    }
    const std::size_t m = kind_ == BvhBuild::Median ? split_median(lo, hi) : split_sah(lo, hi);
    if (hi - lo < kParallelBuild) {
      build(out, lo, m, level + 1, depth);
      const std::uint32_t r = build(out, m, hi, level + 1, depth);
      out[index] = {static_cast<std::uint32_t>(out.size()), r};
      return index;
    }
    // The halves touch disjoint ranges of order_ and only read the triangles.
    std::vector<BvhNode> left, right;
    std::uint32_t dl = 0, dr = 0;
    ex_.invoke([&] { build(left, lo, m, level + 1, dl); }, [&] { build(right, m, hi, level + 1, dr); });
    depth = std::max({depth, dl, dr});
    splice(out, left);
    const auto r = static_cast<std::uint32_t>(out.size());
    splice(out, right);
    out[index] = {static_cast<std::uint32_t>(out.size()), r};
    return index;
  }

  /// Appends a subtree built from index 0: its node indices move by where it lands (a leaf's
  /// triangle range does not).
  static void splice(std::vector<BvhNode>& out, const std::vector<BvhNode>& sub) {
    const auto base = static_cast<std::uint32_t>(out.size());
    for (std::uint32_t i = 0; i < sub.size(); ++i) {
      const bool leaf = sub[i].end == i + 1;
      out.push_back({sub[i].end + base, leaf ? sub[i].right_or_leaf : sub[i].right_or_leaf + base});
    }
  }

  const Vec3& c(std::uint32_t t) const { return tris_[t].centroid; }

  void centroid_bounds(std::size_t lo, std::size_t hi, Vec3& mn, Vec3& mx) const {
    mn = Vec3::Constant(kInf), mx = -mn;
    for (std::size_t i = lo; i < hi; ++i) {
      mn = mn.cwiseMin(c(order_[i]));
      mx = mx.cwiseMax(c(order_[i]));
    }
  }

  /// Ranges of at least this many triangles find their split's bounds and bins in chunks of
  /// kSplitChunk in parallel (the top splits of a large mesh were the build's serial part).
  /// Each chunk's minima, maxima and counts are merged afterwards: the same values in any
  /// order, so the split does not depend on the chunks or the thread count.
  static constexpr std::size_t kParallelSplit = 4 * kParallelBuild, kSplitChunk = 8192;
  static constexpr int kBins = 32;  // fewer bins place the splits coarser: more volume tests
  struct Bins {
    std::array<std::array<Box, kBins>, 3> box;
    std::array<std::array<std::size_t, kBins>, 3> count{};
    void add(const Bins& o) {
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < kBins; ++b) box[a][b].grow(o.box[a][b]), count[a][b] += o.count[a][b];
    }
  };

  /// The range's triangles by bin of their centroids (`mn` its lower corner, `scale` bins per
  /// unit along each axis).
  void fill_bins(std::size_t lo, std::size_t hi, const Vec3& mn, const Vec3& scale, Bins& bins) const {
    for (std::size_t i = lo; i < hi; ++i) {
      const TriangleBounds& t = tris_[order_[i]];
      for (int axis = 0; axis < 3; ++axis) {
        const int b = std::min(kBins - 1, static_cast<int>((t.centroid[axis] - mn[axis]) * scale[axis]));
        bins.box[axis][b].grow(Box{t.lo, t.hi});
        ++bins.count[axis][b];
      }
    }
  }

  /// centroid_bounds and fill_bins of [lo, hi), in chunks in parallel where it is large.
  void bin(std::size_t lo, std::size_t hi, Vec3& mn, Vec3& mx, Vec3& scale, Bins& bins) const {
    auto scales = [&] {
      for (int axis = 0; axis < 3; ++axis) {
        const double ext = mx[axis] - mn[axis];
        scale[axis] = ext > 0 ? kBins / ext : 0.0;
      }
    };
    if (hi - lo < kParallelSplit) {
      centroid_bounds(lo, hi, mn, mx);
      scales();
      fill_bins(lo, hi, mn, scale, bins);
      return;
    }
    const std::size_t chunks = (hi - lo + kSplitChunk - 1) / kSplitChunk;
    auto each_chunk = [&](auto&& body) {
      ex_.static_for(chunks, 1, [&](std::size_t cb, std::size_t ce) {
        for (std::size_t k = cb; k < ce; ++k) body(k, lo + k * kSplitChunk, std::min(hi, lo + (k + 1) * kSplitChunk));
      });
    };
    std::vector<std::array<Vec3, 2>> corner(chunks);
    each_chunk([&](std::size_t k, std::size_t b, std::size_t e) { centroid_bounds(b, e, corner[k][0], corner[k][1]); });
    mn = Vec3::Constant(kInf), mx = -mn;
    for (const auto& [a, b] : corner) mn = mn.cwiseMin(a), mx = mx.cwiseMax(b);
    scales();
    std::vector<Bins> part(chunks);
    each_chunk([&](std::size_t k, std::size_t b, std::size_t e) { fill_bins(b, e, mn, scale, part[k]); });
    for (const Bins& p : part) bins.add(p);
  }

  /// Half by count along `axis` (ties by id, so the result is deterministic).
  std::size_t split_count(std::size_t lo, std::size_t hi, int axis) {
    const std::size_t m = lo + (hi - lo) / 2;
    std::nth_element(order_.begin() + std::ptrdiff_t(lo), order_.begin() + std::ptrdiff_t(m),
                     order_.begin() + std::ptrdiff_t(hi), [&](std::uint32_t a, std::uint32_t b) {
                       return c(a)[axis] != c(b)[axis] ? c(a)[axis] < c(b)[axis] : a < b;
                     });
    return m;
  }

  /// The paper's rule: the longest axis of the centroid bounds at its midpoint.
  std::size_t split_median(std::size_t lo, std::size_t hi) {
    Vec3 mn, mx;
    centroid_bounds(lo, hi, mn, mx);
    int axis = 0;
    (mx - mn).maxCoeff(&axis);
    const double mid = 0.5 * (mn[axis] + mx[axis]);
    auto split = std::stable_partition(order_.begin() + std::ptrdiff_t(lo), order_.begin() + std::ptrdiff_t(hi),
                                       [&](std::uint32_t t) { return c(t)[axis] < mid; });
    const auto m = static_cast<std::size_t>(split - order_.begin());
    return (m == lo || m == hi) ? split_count(lo, hi, axis) : m;  // all on one side: by count
  }

  /// Binned surface area heuristic over the triangles' boxes: for each axis, 32 bins of the
  /// centroid bounds (filled in one pass over the triangles for all three axes); the split
  /// minimising area(left) * leaves(left) + area(right) * leaves(right), leaves(n) = the
  /// leaves n triangles make at least (n / max_leaf, rounded up).
  std::size_t split_sah(std::size_t lo, std::size_t hi) {
    Vec3 mn, mx, scale;
    Bins bins;
    bin(lo, hi, mn, mx, scale, bins);
    // A side's cost counts the leaves its triangles will at least make, not the triangles: a
    // leaf pair costs about the same whatever its leaves' fill, so fuller leaves win (with one
    // triangle a leaf, the classic cost).
    auto leaves = [&](std::size_t n) { return double((n + max_leaf_ - 1) / max_leaf_); };
    double best = kInf;
    int best_axis = -1, best_bin = 0;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(scale[axis] > 0)) continue;
      std::array<double, kBins> right_cost{};
      Box acc;
      std::size_t n = 0;
      for (int b = kBins - 1; b > 0; --b) {
        acc.grow(bins.box[axis][b]);
        n += bins.count[axis][b];
        right_cost[b] = acc.half_area() * leaves(n);
      }
      acc = Box{};
      n = 0;
      for (int b = 0; b + 1 < kBins; ++b) {
        acc.grow(bins.box[axis][b]);
        n += bins.count[axis][b];
        const double cost = acc.half_area() * leaves(n) + right_cost[b + 1];
        if (n > 0 && n < hi - lo && cost < best) best = cost, best_axis = axis, best_bin = b;
      }
    }
    if (best_axis < 0) {  // every centroid in one bin: by count along the widest axis
      int axis = 0;
      (mx - mn).maxCoeff(&axis);
      return split_count(lo, hi, axis);
    }
    const double sc = scale[best_axis], origin = mn[best_axis];
    auto split = std::partition(order_.begin() + std::ptrdiff_t(lo), order_.begin() + std::ptrdiff_t(hi),
                                [&](std::uint32_t t) {
                                  return std::min(kBins - 1, static_cast<int>((c(t)[best_axis] - origin) * sc)) <= best_bin;
                                });
    return static_cast<std::size_t>(split - order_.begin());
  }

  const std::vector<TriangleBounds>& tris_;
  BvhBuild kind_;
  std::size_t max_leaf_;
  std::vector<std::uint32_t>& order_;
  std::vector<BvhNode>& nodes_;
  std::vector<std::uint32_t>& node_mesh_;
  const detail::Executor& ex_;
  std::uint32_t depth_ = 0;
};

}  // namespace

std::vector<TriangleBounds> triangle_bounds(const std::vector<Triangle>& faces, const Positions& x,
                                            const detail::Executor& ex) {
  std::vector<TriangleBounds> out;
  detail::reserve_huge(out, faces.size());  // megabytes, new: in huge pages where whole, backed at once
  out.resize(faces.size());
  ex.for_chunks(faces.size(), 8192, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f != end; ++f) {
      const Vec3 a = x.point(faces[f][0]), b = x.point(faces[f][1]), c = x.point(faces[f][2]);
      out[f] = {a.cwiseMin(b).cwiseMin(c), a.cwiseMax(b).cwiseMax(c), (a + b + c) / 3.0};
    }
  });
  return out;
}

namespace {

/// The units of the build: per mesh (`mesh_offsets`; none: one mesh of all `n` triangles), each
/// connected component (triangles joined by shared vertices) that looks closed, F >= 4 even
/// triangles over V = F / 2 + 2 vertices (what a closed surface of Euler characteristic 2 has,
/// each edge shared by two triangles), on its own, then the mesh's other triangles as one unit.
/// Writes the triangle order (units contiguous), the units' offsets into it and their meshes.
void closed_units(std::size_t n, const std::vector<std::size_t>& mesh_offsets, const std::vector<Triangle>& faces,
                  std::vector<std::uint32_t>& order, std::vector<std::size_t>& offsets,
                  std::vector<std::uint32_t>& unit_mesh) {
  std::uint32_t nv = 0;
  for (const Triangle& t : faces) nv = std::max({nv, t[0] + 1, t[1] + 1, t[2] + 1});
  const std::vector<std::uint32_t> root = detail::vertex_components(nv, faces);  // each vertex's component
  std::vector<std::uint32_t> tris(nv, 0), verts(nv, 0);
  for (const Triangle& t : faces) ++tris[root[t[0]]];
  std::vector<std::uint8_t> seen(nv, 0);
  for (const Triangle& t : faces)
    for (std::uint32_t v : t)
      if (!seen[v]) seen[v] = 1, ++verts[root[v]];
  auto closed = [&](std::uint32_t r) { return tris[r] >= 4 && tris[r] % 2 == 0 && verts[r] == tris[r] / 2 + 2; };
  const std::size_t meshes = mesh_offsets.size() > 1 ? mesh_offsets.size() - 1 : 1;
  order.clear();
  detail::reserve_backed(order, n);  // every triangle once, below
  offsets.assign(1, 0);
  unit_mesh.clear();
  std::vector<std::uint32_t> unit_of_root(nv, 0xffffffffu);
  for (std::size_t m = 0; m < meshes; ++m) {
    const std::size_t lo = mesh_offsets.size() > 1 ? mesh_offsets[m] : 0, hi = mesh_offsets.size() > 1 ? mesh_offsets[m + 1] : n;
    if (lo == hi) continue;
    // the closed components in order of their first triangle, then the rest
    std::vector<std::vector<std::uint32_t>> units;
    std::vector<std::uint32_t> rest;
    rest.reserve(hi - lo);  // at most every triangle of the mesh: reserved once, not regrown
    for (std::size_t f = lo; f < hi; ++f) {
      const std::uint32_t r = root[faces[f][0]];
      if (!closed(r)) {
        rest.push_back(static_cast<std::uint32_t>(f));
        continue;
      }
      if (unit_of_root[r] == 0xffffffffu) {
        unit_of_root[r] = static_cast<std::uint32_t>(units.size());
        units.emplace_back();
      }
      units[unit_of_root[r]].push_back(static_cast<std::uint32_t>(f));
    }
    if (!rest.empty()) units.push_back(std::move(rest));
    for (const auto& u : units) {
      order.insert(order.end(), u.begin(), u.end());
      offsets.push_back(order.size());
      unit_mesh.push_back(static_cast<std::uint32_t>(m));
    }
  }
}

}  // namespace

BvhTopology::BvhTopology(const std::vector<TriangleBounds>& triangles, BvhBuild kind, unsigned max_leaf,
                         const std::vector<std::size_t>& mesh_offsets, const std::vector<Triangle>* faces,
                         const detail::Executor& ex)
    : max_leaf_(std::clamp(max_leaf, 1u, kMaxLeaf)) {
  const std::size_t n = triangles.size();
  if (n == 0) return;
  if (n > kMaxTriangles) throw std::length_error("mccd: more than 2^27 triangles in one scene");
  nodes_.reserve(2 * n - 1);
  Builder b(triangles, kind, max_leaf_, nodes_, order_, node_mesh_, ex);
  std::vector<std::size_t> offsets;
  std::vector<std::uint32_t> unit_mesh;
  if (faces && faces->size() == n && kind != BvhBuild::Median) {
    closed_units(n, mesh_offsets, *faces, order_, offsets, unit_mesh);
  } else {
    for (std::size_t m = 0; m + 1 < mesh_offsets.size(); ++m)
      if (mesh_offsets[m + 1] > mesh_offsets[m]) {  // the meshes with triangles
        if (offsets.empty()) offsets.push_back(mesh_offsets[m]);
        offsets.push_back(mesh_offsets[m + 1]);  // the next mesh with triangles starts here
        unit_mesh.push_back(static_cast<std::uint32_t>(m));
      }
  }
  if (unit_mesh.empty()) {
    b.build(0, n, 0);
  } else {
    std::vector<std::uint32_t> ids(unit_mesh.size());
    std::iota(ids.begin(), ids.end(), 0u);
    b.build_units(std::move(ids), offsets, unit_mesh, 0);
  }
  depth_ = b.depth();
}

}  // namespace mccd
