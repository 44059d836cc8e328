#pragma once
/// @file Internal: the time pieces of the BVH's leaves of several triangles, the merge of their
/// triangles' quarter volumes (geometry/swept_volumes.h). An overlapping leaf pair whose leaves
/// meet in no common quarter of the step holds no triangle pair that can meet: it is dropped
/// before any triangle test, and the quarters where the leaves meet bound the quarters tested
/// below (every triangle's volumes lie inside its leaf's).
#include <cstdint>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/geometry/swept_volumes.h>

namespace mccd::detail {

template <BoundingVolume BV>
class LeafPieces {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  /// Numbers the leaves of several triangles; `moving(node)` says whether a leaf's triangles
  /// move (a static mesh's leaves are computed once, by the first update).
  template <class Moving>
  void plan(const BvhTopology& bvh, const Moving& moving) {
    index_.assign(bvh.size(), kNone);
    for (std::uint32_t i = 0; i < bvh.size(); ++i)
      if (bvh.leaf(i) && bvh.leaf_count(i) > 1) {
        index_[i] = static_cast<std::uint32_t>(leaves_.size());
        leaves_.push_back(i);
        if (moving(i)) moving_.push_back(static_cast<std::uint32_t>(leaves_.size() - 1));
      }
    pieces_.resize(leaves_.size());
  }

  /// Leaves [begin, end) of the moving ones (all of them with `all`), after the faces' pieces.
  void update(const BvhTopology& bvh, const SweptVolumes<BV>& swept, std::size_t begin, std::size_t end, bool all) {
    for (std::size_t k = begin; k != end; ++k) {
      const std::uint32_t leaf = all ? static_cast<std::uint32_t>(k) : moving_[k];
      const std::uint32_t node = leaves_[leaf];
      const std::uint32_t* t = bvh.leaf_triangles(node);
      PieceVolumes<BV> p = swept.face_pieces(t[0]);
      for (std::uint32_t i = 1; i < bvh.leaf_count(node); ++i) p = merged_pieces(p, swept.face_pieces(t[i]));
      pieces_[leaf] = p;
    }
  }
  std::size_t num_moving() const { return moving_.size(); }
  std::size_t num_leaves() const { return leaves_.size(); }

  /// The quarters in which BVH leaves a and b (each of several triangles, or not: then all
  /// four) may meet.
  unsigned quarters(std::uint32_t a, std::uint32_t b) const {
    const std::uint32_t ia = index_[a], ib = index_[b];
    if (ia == kNone || ib == kNone) return 0xF;
    const auto &pa = pieces_[ia], &pb = pieces_[ib];
    return meeting_quarters([&](int q) { return pa[q].overlaps(pb[q]); });
  }

 private:
  std::vector<std::uint32_t> index_;   ///< per BVH node: its leaf number, or kNone
  std::vector<std::uint32_t> leaves_;  ///< per leaf number: its node
  std::vector<std::uint32_t> moving_;  ///< leaf numbers of the moving leaves
  std::vector<PieceVolumes<BV>> pieces_;
};

}  // namespace mccd::detail
