#include <mccd/core/bvh.h>

#include <algorithm>
#include <limits>
#include <numeric>

namespace mccd {

namespace {
struct Builder {
  const std::vector<Vec3>& c;
  std::vector<std::uint32_t> order;
  std::vector<BvhNode>& nodes;
  std::vector<std::uint32_t>& leaf_of;
  std::uint32_t depth = 0;

  // Builds the subtree over order[lo, hi) at node index nodes.size(); returns its index.
  std::uint32_t build(std::size_t lo, std::size_t hi, std::uint32_t level) {
    const auto index = static_cast<std::uint32_t>(nodes.size());
    nodes.push_back({0, 0});
    depth = std::max(depth, level);
    if (hi - lo == 1) {
      nodes[index] = {index + 1, order[lo]};
      leaf_of[order[lo]] = index;
      return index;
    }
    Vec3 mn = Vec3::Constant(std::numeric_limits<double>::infinity()), mx = -mn;
    for (std::size_t i = lo; i < hi; ++i) {
      mn = mn.cwiseMin(c[order[i]]);
      mx = mx.cwiseMax(c[order[i]]);
    }
    int axis = 0;
    (mx - mn).maxCoeff(&axis);
    const double mid = 0.5 * (mn[axis] + mx[axis]);
    auto first = order.begin() + static_cast<std::ptrdiff_t>(lo), last = order.begin() + static_cast<std::ptrdiff_t>(hi);
    auto split = std::stable_partition(first, last, [&](std::uint32_t t) { return c[t][axis] < mid; });
    std::size_t m = static_cast<std::size_t>(split - order.begin());
    if (m == lo || m == hi) {  // all centroids on one side: median by count
      m = lo + (hi - lo) / 2;
      std::nth_element(first, order.begin() + static_cast<std::ptrdiff_t>(m), last, [&](std::uint32_t a, std::uint32_t b) {
        return c[a][axis] != c[b][axis] ? c[a][axis] < c[b][axis] : a < b;
      });
    }
    build(lo, m, level + 1);
    const std::uint32_t r = build(m, hi, level + 1);
    nodes[index] = {static_cast<std::uint32_t>(nodes.size()), r};
    return index;
  }
};
}  // namespace

BvhTopology::BvhTopology(const std::vector<Vec3>& centroids) {
  const std::size_t n = centroids.size();
  if (n == 0) return;
  nodes_.reserve(2 * n - 1);
  leaf_of_.assign(n, 0);
  Builder b{centroids, std::vector<std::uint32_t>(n), nodes_, leaf_of_};
  std::iota(b.order.begin(), b.order.end(), 0u);
  b.build(0, n, 0);
  depth_ = b.depth;
}

}  // namespace mccd
