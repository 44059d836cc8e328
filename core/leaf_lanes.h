#pragma once
/// @file Internal: per BVH leaf, the coarse whole-step volumes (geometry/coarse_volumes.h) of
/// its features as lane blocks (geometry/lane_masks.h): the vertices and the edges it owns
/// (leaf rule, core/leaf_rule_owners.h) and its faces, in slot order, and the leaf's own coarse
/// volume. A leaf pair first tests a feature of one leaf against every feature of the other
/// in lanes on these; only the pairs they do not separate read the float volumes.
///
/// Blocks are laid out leaf after leaf (vertices, edges, faces), each with a stride of its lane
/// count rounded up to a power of two (at least 8). Each step, quantize_vertices() computes
/// every vertex's coarse volume from its float one, and a leaf's lanes are written from those
/// the first time a leaf pair or the self stage asks for them (ensure()): they are in the cache
/// then, and a leaf never asked for costs nothing (a closed body certified whole). A leaf that
/// repeats the previous step (core/unchanged_leaves.h; a static mesh's, a resting part's) and
/// had its lanes then, on the same grid, keeps them: writing them is most of a fill's cost.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/core/executor.h>
#include <mccd/core/leaf_rule_owners.h>
#include <mccd/core/options.h>
#include <mccd/geometry/coarse_volumes.h>
#include <mccd/geometry/lane_masks.h>
#include <mccd/geometry/large_allocator.h>
#include <mccd/geometry/swept_volumes.h>

namespace mccd::detail {

template <BoundingVolume BV>
class LeafLanes {
 public:
  static constexpr int kSlabs = BV::kSlabs;
  static constexpr unsigned kRows = 2 * kSlabs;
  using Grid = CoarseGrid<kSlabs>;

  /// One block: row r at rows + r * stride, lanes [0, n).
  struct Block {
    const std::int16_t* rows;
    unsigned stride, n;
  };

  LeafLanes() = default;
  /// Room for every leaf of `bvh` (first_touch() zeroes it; ensure() fills a leaf's lanes),
  /// and the corner lanes of every edge's ends and face's corners (per leaf, through `ex`).
  LeafLanes(const BvhTopology& bvh, const LeafOwnership& owners, const Executor& ex = serial_executor()) {
    offset_.assign(std::size_t(3) * bvh.size(), 0);
    source_.assign(bvh.size(), kNone);
    std::size_t total = 0, sources = 0;
    for (std::uint32_t node = 0; node < bvh.size(); ++node) {
      if (!bvh.leaf(node)) continue;
      offset_[3 * node] = static_cast<std::uint32_t>(total);
      total += std::size_t(kRows) * stride(corners(node, owners));
      offset_[3 * node + 1] = static_cast<std::uint32_t>(total);
      total += std::size_t(kRows) * stride(owners.edge_begin(node + 1) - owners.edge_begin(node));
      offset_[3 * node + 2] = static_cast<std::uint32_t>(total);
      total += std::size_t(kRows) * stride(bvh.leaf_count(node));
      if (total > 0xffffffffu - kLaneSlack) throw std::length_error("mccd: scene too large for its leaf lanes");
      source_[node] = static_cast<std::uint32_t>(sources++);
    }
    sources_.resize(sources);
    populate_pages(sources_.data(), sources * sizeof(Sources));  // written in full below
    // Each leaf's entries written by its own chunk (a leaf's work grows with the square of its
    // corners: small chunks, dealt out as threads free up).
    const std::vector<std::uint32_t>& slot_of = owners.layout().vertex_slot;
    ex.dynamic_for(bvh.size(), 128, [&](std::size_t begin, std::size_t end) {
      for (auto node = static_cast<std::uint32_t>(begin); node != end; ++node)
        if (bvh.leaf(node)) fill_sources(node, bvh, owners, slot_of);
    });
    values_.resize(total + kLaneSlack);
    leaf_.resize(bvh.size());
    still_.assign(bvh.size(), 0);
    stamp_ = std::make_unique<std::atomic<std::uint32_t>[]>(bvh.size());  // zero: never filled
    valid_.assign(bvh.size(), 0);
    vertices_.resize(owners.layout().vertex_slot.size());
  }

  bool empty() const { return values_.empty(); }

  /// Zeroes the storage through `for_chunks` (first_touch in geometry/large_allocator.h).
  template <class ForChunks>
  void first_touch(const ForChunks& for_chunks) {
    detail::first_touch(values_, for_chunks);
    detail::first_touch(leaf_, for_chunks);
    detail::first_touch(vertices_, for_chunks);
  }

  /// The coarse volumes of vertex slots [begin, end) on the step's grid (begin()), from
  /// `swept` (after the step's update; before any leaf is filled).
  void quantize_vertices(std::size_t begin, std::size_t end, const SweptVolumes<BV>& swept) {
    for (std::size_t s = begin; s != end; ++s)
      quantize_vertex(s, swept.vertex_quarters_at(static_cast<std::uint32_t>(s)));
  }
  /// The same for one vertex slot from its quarter volumes (during the update's pass).
  void quantize_vertex(std::size_t slot, const QuarterVolume<BV>& quarters) {
    quantize(grid_, quarters.whole(), vertices_[slot]);
  }

  /// Where quantize_vertex() writes, for a kernel that writes the same itself
  /// (LaneKernels::vertex_quarters): the step's grid and the coarse volume of each vertex slot.
  CoarseOut coarse_out() { return {grid_.origin, grid_.scale, vertices_.data()}; }

  /// A new step on `grid`: every leaf's lanes are stale until filled again (ensure()).
  /// Returns whether every vertex slot's coarse volume from the last update still holds: that
  /// update completed (vertices_done()) and `grid` is its grid, bit for bit. The update then
  /// need not quantize the slots whose quarter volumes it keeps (they are those of then).
  bool begin(const Grid& grid) {
    const bool hold = vertices_hold_ && std::memcmp(&grid, &grid_, sizeof(Grid)) == 0;
    vertices_hold_ = false;  // until this step's update completes
    grid_held_ = hold;
    grid_ = grid;
    if (++epoch_ == 0x7fffffffu) {  // stamps would wrap: every leaf stale explicitly
      epoch_ = 1;
      for (std::size_t i = 0; i < leaf_.size(); ++i) stamp_[i].store(0, std::memory_order_relaxed);
      std::fill(valid_.begin(), valid_.end(), 0u);
      grid_held_ = false;
    }
    return hold;
  }
  /// The update since begin() completed: every vertex slot's coarse volume is on the grid.
  void vertices_done() { vertices_hold_ = true; }

  /// Leaf `node`'s lanes, filled for this step when they are not yet (its vertices' coarse
  /// volumes from quantize_vertices(), its own from `volume`, the step's quarter volume of the
  /// leaf). Safe from several threads: one fills, the others wait for it. `repeats`: every
  /// corner of the leaf has the start and end positions of the previous step (and so its
  /// volume): lanes it had in that step, on this step's grid, are kept as they are.
  void ensure(std::uint32_t node, const BvhTopology& bvh, const LeafOwnership& owners, const QuarterVolume<BV>& volume,
              bool repeats = false) const {
    const std::uint32_t done = 2 * epoch_, busy = done + 1;
    std::atomic<std::uint32_t>& stamp = stamp_[node];
    std::uint32_t s = stamp.load(std::memory_order_acquire);
    if (s == done) return;
    if (s != busy && stamp.compare_exchange_strong(s, busy, std::memory_order_acquire)) {
      // the lanes hold the previous step's values, which are this step's
      const bool kept = repeats && grid_held_ && valid_[node] + 1 == epoch_;
      if (!kept) const_cast<LeafLanes*>(this)->fill(node, bvh, owners, volume);
      valid_[node] = epoch_;  // only the thread that holds the leaf busy writes it
      stamp.store(done, std::memory_order_release);
      return;
    }
    while (stamp.load(std::memory_order_acquire) != done) std::this_thread::yield();
  }

 private:
  /// The corner lane of each of leaf `node`'s edges' ends and faces' corners: its own vertices
  /// first, then the others'.
  void fill_sources(std::uint32_t node, const BvhTopology& bvh, const LeafOwnership& owners,
                    const std::vector<std::uint32_t>& slot_of) {
    const std::uint32_t vb = owners.vertex_begin(node), nv = owners.vertex_begin(node + 1) - vb;
    const std::uint32_t fb = owners.foreign_begin(node), nf = owners.foreign_begin(node + 1) - fb;
    auto lane = [&](std::uint32_t slot) -> std::uint8_t {
      if (slot - vb < nv) return static_cast<std::uint8_t>(slot - vb);
      for (std::uint32_t i = 0; i < nf; ++i)
        if (owners.foreign_corner(fb + i) == slot) return static_cast<std::uint8_t>(nv + i);
      throw std::logic_error("mccd: a leaf's corner list misses a corner");
    };
    Sources& own = sources_[source_[node]];
    std::memset(&own, 0, sizeof own);  // whole: the lanes past its features read as lane 0
    std::uint8_t(*src)[kMaxLanes] = own.lane;
    for (std::uint32_t j = 0, e = owners.edge_begin(node); e != owners.edge_begin(node + 1); ++j, ++e) {
      const Edge& ends = owners.edge_ends(e);
      src[0][j] = lane(slot_of[ends[0]]);
      src[1][j] = lane(slot_of[ends[1]]);
    }
    for (std::uint32_t k = 0; k < bvh.leaf_count(node); ++k) {
      const Triangle& c = owners.face_corner_slots(bvh.leaf_first(node) + k);
      for (int i = 0; i < 3; ++i) src[2 + i][k] = lane(c[i]);
    }
  }

  /// Leaf `node`'s lanes from the coarse volumes of the vertices (quantize_vertices()): its
  /// corners' (its own vertices', then the others'), then from those its edges' (the merge of
  /// their ends') and its faces' (of their corners'), in lanes (LaneKernels::merge_lanes).
  void fill(std::uint32_t node, const BvhTopology& bvh, const LeafOwnership& owners, const QuarterVolume<BV>& volume) {
    const std::uint32_t vb = owners.vertex_begin(node), nv = owners.vertex_begin(node + 1) - vb;
    const std::uint32_t fb = owners.foreign_begin(node), nf = owners.foreign_begin(node + 1) - fb;
    std::int16_t* corners = values_.data() + offset_[3 * node];
    const unsigned cs = stride(nv + nf);
    // the other corners' volumes lie elsewhere: asked for before the own ones are scattered
    for (std::uint32_t i = 0; i < nf; ++i) __builtin_prefetch(&vertices_[owners.foreign_corner(fb + i)]);
    for (std::uint32_t j = 0; j < nv; ++j) scatter(vertices_[vb + j], corners + j, cs);
    for (std::uint32_t i = 0; i < nf; ++i) scatter(vertices_[owners.foreign_corner(fb + i)], corners + nv + i, cs);
    const std::uint8_t(*src)[kMaxLanes] = sources_[source_[node]].lane;
    const LaneKernels& k = lane_kernels();
    const unsigned ne = owners.edge_begin(node + 1) - owners.edge_begin(node);
    k.merge_lanes(corners, cs, kSlabs, src, 2, ne, values_.data() + offset_[3 * node + 1], stride(ne));
    const unsigned nt = bvh.leaf_count(node);
    k.merge_lanes(corners, cs, kSlabs, src + 2, 3, nt, values_.data() + offset_[3 * node + 2], stride(nt));
    quantize(grid_, volume.whole(), leaf_[node]);
    still_[node] = still_rule(corners, cs, nv + nf, values_.data() + offset_[3 * node + 1], stride(ne), ne);
  }

  /// Whether a leaf moves little against its edges' lengths this step (set_order()): its
  /// corners' coarse volumes, the largest coordinate extent of each (about its displacement),
  /// averaged, below a quarter of its edges' (about their lengths), averaged. Cloth-ball's
  /// leaves: 0.07-0.14 (10th-90th percentile) in its sub-steps, 0.44-0.77 in its whole step.
  bool still_rule(const std::int16_t* corners, unsigned cs, unsigned nc, const std::int16_t* edges, unsigned es,
                  unsigned ne) const {
    if (order_ != VolumeOrder::Adaptive) return order_ == VolumeOrder::AfterFilter;
    if (ne == 0) return false;
    auto extents = [](const std::int16_t* rows, unsigned stride, unsigned n) {
      long sum = 0;
      for (unsigned j = 0; j < n; ++j) {
        int e = 0;
        for (int a = 0; a < 3; ++a) e = std::max(e, int(rows[(kSlabs + a) * stride + j]) - int(rows[a * stride + j]));
        sum += e;
      }
      return sum;
    };
    return 4 * extents(corners, cs, nc) * long(ne) < extents(edges, es, ne) * long(nc);
  }

 public:
  /// How still() decides (SceneOptions::volume_order): Adaptive by still_rule(), First never,
  /// AfterFilter always.
  void set_order(VolumeOrder order) { order_ = order; }
  /// Whether leaf `node`'s feature pairs have their quarter volumes tested after the
  /// coplanarity filter (core/leaf_rule_pairs.h): its lanes filled this step, it moves little
  /// against its edges' lengths (still_rule()).
  bool still(std::uint32_t node) const { return still_[node] != 0; }

  /// Leaf `node`'s blocks: its owned vertices and edges (lane j: slot vertex_begin(node) + j,
  /// edge_begin(node) + j), its faces (lane k: face slot leaf_first(node) + k). (The vertices'
  /// block is the first lanes of its corners'.)
  Block vertices(std::uint32_t node, const LeafOwnership& owners) const {
    const unsigned n = owners.vertex_begin(node + 1) - owners.vertex_begin(node);
    return {values_.data() + offset_[3 * node], stride(corners(node, owners)), n};
  }
  Block edges(std::uint32_t node, const LeafOwnership& owners) const {
    const unsigned n = owners.edge_begin(node + 1) - owners.edge_begin(node);
    return {values_.data() + offset_[3 * node + 1], stride(n), n};
  }
  Block faces(std::uint32_t node, const BvhTopology& bvh) const {
    const unsigned n = bvh.leaf_count(node);
    return {values_.data() + offset_[3 * node + 2], stride(n), n};
  }
  /// All of leaf `node`'s blocks and its own coarse volume, for the kernels.
  LeafBlocks blocks(std::uint32_t node, const BvhTopology& bvh, const LeafOwnership& owners) const {
    const Block v = vertices(node, owners), e = edges(node, owners), f = faces(node, bvh);
    return {v.rows, v.stride, v.n, e.rows, e.stride, e.n, f.rows, f.stride, f.n, &leaf_[node]};
  }
  /// Vertex slot `slot`'s coarse volume (quantize_vertices()).
  const CoarseDop& vertex(std::uint32_t slot) const { return vertices_[slot]; }
  /// The step's grid (begin()).
  const Grid& grid() const { return grid_; }
  /// Whether leaf `node`'s lanes are this step's (ensure() since begin()).
  bool filled(std::uint32_t node) const { return stamp_[node].load(std::memory_order_acquire) == 2 * epoch_; }

 private:
  static constexpr std::uint32_t kNone = 0xffffffffu;
  static unsigned corners(std::uint32_t node, const LeafOwnership& owners) {
    return owners.vertex_begin(node + 1) - owners.vertex_begin(node) + owners.foreign_begin(node + 1) -
           owners.foreign_begin(node);
  }

  /// A block's row length: a power of two from 8 to 64 lanes.
  static unsigned stride(unsigned n) { return n <= 8 ? 8 : n <= 16 ? 16 : n <= 32 ? 32 : 64; }

  static void quantize(const Grid& grid, const BV& d, CoarseDop& c) {
    std::int16_t v[kRows];
    grid.quantize(d, v);
    for (int k = 0; k < 16; ++k) {
      c.lo[k] = k < kSlabs ? v[k] : std::int16_t(0);
      c.hi[k] = k < kSlabs ? v[kSlabs + k] : std::int16_t(0);
    }
  }

  static void scatter(const CoarseDop& d, std::int16_t* lane, unsigned stride) {
    for (int s = 0; s < kSlabs; ++s) {
      lane[s * stride] = d.lo[s];
      lane[(kSlabs + s) * stride] = d.hi[s];
    }
  }

  std::vector<std::uint32_t> offset_;  ///< per node: its corner, edge and face block
  std::vector<std::uint32_t> source_;  ///< per leaf: its first entry in sources_
  /// per leaf: the corner lanes of its edges' two ends (lane[0], lane[1]) and of its faces'
  /// three corners (lane[2..4])
  struct Sources {
    std::uint8_t lane[5][kMaxLanes];
  };
  LargeVector<Sources> sources_;  ///< uninitialised until each leaf's chunk writes its own
  LargeVector<std::int16_t> values_;
  Grid grid_{};
  bool vertices_hold_ = false;  ///< vertices_done() since the last begin()
  bool grid_held_ = false;      ///< begin() found the last step's grid, its coarse volumes done
  mutable std::vector<std::uint32_t> valid_;  ///< per node: the last epoch its lanes were this step's
  std::uint32_t epoch_ = 0;  ///< steps begun: a leaf's lanes are this step's when its stamp is 2 epoch_
  std::unique_ptr<std::atomic<std::uint32_t>[]> stamp_;  ///< per node: 2 e filled at step e, 2 e + 1 filling
  LargeVector<CoarseDop> leaf_;      ///< per node: a leaf's own coarse volume
  std::vector<std::uint8_t> still_;  ///< per node: still() this step
  VolumeOrder order_ = VolumeOrder::Adaptive;
  LargeVector<CoarseDop> vertices_;  ///< per vertex slot: its coarse volume
};

}  // namespace mccd::detail
