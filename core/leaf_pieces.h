#pragma once
/// @file Internal: the quarter volumes of the BVH's leaves, each the merge of the quarter
/// volumes of its triangles' corners (geometry/swept_volumes.h). Two overlapping leaves that
/// meet in no common quarter of the step hold no feature pair that can meet: the pair is
/// dropped before any feature test, and the quarters where the leaves meet bound the quarters
/// tested below (every feature's quarter volumes lie inside its leaf's).
#include <algorithm>
#include <cstdint>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/geometry/swept_volumes.h>

namespace mccd::detail {

template <BoundingVolume BV>
class LeafPieces {
 public:
  using Quarters = QuarterVolume<BV>;
  static constexpr std::uint32_t kNone = 0xffffffffu;

  /// Numbers the leaves; `moving(node)` says whether a leaf's triangles move (a static mesh's
  /// leaves are computed once, by update(all = true)).
  template <class Moving>
  void plan(const BvhTopology& bvh, const MeshTopology& topo, const Moving& moving) {
    index_.assign(bvh.size(), kNone);
    corner_begin_.assign(1, 0);
    for (std::uint32_t i = 0; i < bvh.size(); ++i)
      if (bvh.leaf(i)) {
        index_[i] = static_cast<std::uint32_t>(leaves_.size());
        leaves_.push_back(i);
        if (moving(i)) moving_.push_back(static_cast<std::uint32_t>(leaves_.size() - 1));
        // the leaf's distinct corners
        const std::size_t first = corners_.size();
        const std::uint32_t* t = bvh.leaf_triangles(i);
        for (std::uint32_t k = 0; k < bvh.leaf_count(i); ++k)
          for (std::uint32_t v : topo.faces()[t[k]])
            if (std::find(corners_.begin() + static_cast<std::ptrdiff_t>(first), corners_.end(), v) == corners_.end())
              corners_.push_back(v);
        corner_begin_.push_back(static_cast<std::uint32_t>(corners_.size()));
      }
    pieces_.resize(leaves_.size());
  }

  /// Leaves [begin, end) of the moving ones (of all of them with `all`), after the vertices'
  /// quarters.
  void update(const SweptVolumes<BV>& swept, std::size_t begin, std::size_t end, bool all) {
    for (std::size_t k = begin; k != end; ++k) {
      const std::uint32_t leaf = all ? static_cast<std::uint32_t>(k) : moving_[k];
      const std::uint32_t* c = corners_.data() + corner_begin_[leaf];
      const std::uint32_t n = corner_begin_[leaf + 1] - corner_begin_[leaf];
      Quarters p = swept.vertex_quarters(c[0]);
      for (std::uint32_t i = 1; i < n; ++i) p.merge(swept.vertex_quarters(c[i]));
      pieces_[leaf] = p;
    }
  }
  std::size_t num_moving() const { return moving_.size(); }
  std::size_t num_leaves() const { return leaves_.size(); }

  /// The quarter volumes of BVH leaf node `node`.
  const Quarters& of(std::uint32_t node) const { return pieces_[index_[node]]; }
  /// The quarters in which BVH leaves a and b may meet.
  unsigned quarters(std::uint32_t a, std::uint32_t b) const { return of(a).overlap_mask(of(b)); }

 private:
  std::vector<std::uint32_t> index_;   ///< per BVH node: its leaf number, or kNone
  std::vector<std::uint32_t> leaves_;  ///< per leaf number: its node
  std::vector<std::uint32_t> moving_;  ///< leaf numbers of the moving leaves
  std::vector<std::uint32_t> corner_begin_, corners_;  ///< per leaf number: its distinct corners
  std::vector<Quarters> pieces_;
};

}  // namespace mccd::detail
