#pragma once
/// @file Internal: per BVH leaf, the coarse whole-step volumes (geometry/coarse_volumes.h) of
/// its features as lane blocks (geometry/lane_masks.h): the vertices and the edges it owns
/// (leaf rule, core/leaf_owners.h) and its faces, in slot order, and the leaf's own coarse
/// volume. A leaf pair first tests a feature of one leaf against every feature of the other
/// in lanes on these; only the pairs they do not separate read the float volumes.
///
/// Blocks are laid out leaf after leaf (vertices, edges, faces), each with a stride of its lane
/// count rounded up to a power of two (at least 8). Each step, quantize_vertices() computes
/// every vertex's coarse volume from its float one, and a leaf's lanes are written from those
/// the first time a leaf pair or the self stage asks for them (ensure()): they are in the cache
/// then, and a leaf never asked for costs nothing (a closed body certified whole).
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/core/leaf_owners.h>
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
  /// Room for every leaf of `bvh` (first_touch() zeroes it; ensure() fills a leaf's lanes).
  LeafLanes(const BvhTopology& bvh, const LeafOwnership& owners) {
    offset_.assign(std::size_t(3) * bvh.size(), 0);
    std::size_t total = 0;
    for (std::uint32_t node = 0; node < bvh.size(); ++node) {
      if (!bvh.leaf(node)) continue;
      offset_[3 * node] = static_cast<std::uint32_t>(total);
      total += std::size_t(kRows) * stride(owners.vertex_begin(node + 1) - owners.vertex_begin(node));
      offset_[3 * node + 1] = static_cast<std::uint32_t>(total);
      total += std::size_t(kRows) * stride(owners.edge_begin(node + 1) - owners.edge_begin(node));
      offset_[3 * node + 2] = static_cast<std::uint32_t>(total);
      total += std::size_t(kRows) * stride(bvh.leaf_count(node));
      if (total > 0xffffffffu - kLaneSlack) throw std::length_error("mccd: scene too large for its leaf lanes");
    }
    values_.resize(total + kLaneSlack);
    leaf_.resize(bvh.size());
    stamp_ = std::make_unique<std::atomic<std::uint32_t>[]>(bvh.size());  // zero: never filled
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
      quantize(grid_, swept.vertex_at(static_cast<std::uint32_t>(s)), vertices_[s]);
  }

  /// A new step on `grid`: every leaf's lanes are stale until filled again (ensure()).
  void begin(const Grid& grid) {
    grid_ = grid;
    if (++epoch_ == 0x7fffffffu) {  // stamps would wrap: every leaf stale explicitly
      epoch_ = 1;
      for (std::size_t i = 0; i < leaf_.size(); ++i) stamp_[i].store(0, std::memory_order_relaxed);
    }
  }

  /// Leaf `node`'s lanes, filled for this step when they are not yet (its vertices' coarse
  /// volumes from quantize_vertices(), its own from `volume`, the step's quarter volume of the
  /// leaf). Safe from several threads: one fills, the others wait for it.
  void ensure(std::uint32_t node, const BvhTopology& bvh, const LeafOwnership& owners, const SweptVolumes<BV>& swept,
              const QuarterVolume<BV>& volume) const {
    const std::uint32_t done = 2 * epoch_, busy = done + 1;
    std::atomic<std::uint32_t>& stamp = stamp_[node];
    std::uint32_t s = stamp.load(std::memory_order_acquire);
    if (s == done) return;
    if (s != busy && stamp.compare_exchange_strong(s, busy, std::memory_order_acquire)) {
      const_cast<LeafLanes*>(this)->fill(node, bvh, owners, swept, volume);
      stamp.store(done, std::memory_order_release);
      return;
    }
    while (stamp.load(std::memory_order_acquire) != done) std::this_thread::yield();
  }

 private:
  /// Leaf `node`'s lanes from the coarse volumes of the vertices (quantize_vertices()): its
  /// vertices', its edges' (the merge of their ends') and its faces' (of their corners').
  void fill(std::uint32_t node, const BvhTopology& bvh, const LeafOwnership& owners, const SweptVolumes<BV>& swept,
            const QuarterVolume<BV>& volume) {
    {
      const std::uint32_t b = owners.vertex_begin(node), n = owners.vertex_begin(node + 1) - b;
      std::int16_t* rows = values_.data() + offset_[3 * node];
      const unsigned st = stride(n);
      for (std::uint32_t j = 0; j < n; ++j) scatter(vertices_[b + j], rows + j, st);
    }
    {
      const std::uint32_t b = owners.edge_begin(node), n = owners.edge_begin(node + 1) - b;
      std::int16_t* rows = values_.data() + offset_[3 * node + 1];
      const unsigned st = stride(n);
      for (std::uint32_t j = 0; j < n; ++j) {
        const Edge& e = swept.edge_end_slots_at(b + j);
        scatter(merged(vertices_[e[0]], vertices_[e[1]]), rows + j, st);
      }
    }
    {
      const std::uint32_t b = bvh.leaf_first(node), n = bvh.leaf_count(node);
      std::int16_t* rows = values_.data() + offset_[3 * node + 2];
      const unsigned st = stride(n);
      for (std::uint32_t j = 0; j < n; ++j) {
        const Triangle& c = owners.face_corner_slots(b + j);
        scatter(merged(merged(vertices_[c[0]], vertices_[c[1]]), vertices_[c[2]]), rows + j, st);
      }
    }
    quantize(grid_, volume.whole(), leaf_[node]);
  }

 public:

  /// Leaf `node`'s blocks: its owned vertices and edges (lane j: slot vertex_begin(node) + j,
  /// edge_begin(node) + j), its faces (lane k: face slot leaf_first(node) + k).
  Block vertices(std::uint32_t node, const LeafOwnership& owners) const {
    const unsigned n = owners.vertex_begin(node + 1) - owners.vertex_begin(node);
    return {values_.data() + offset_[3 * node], stride(n), n};
  }
  Block edges(std::uint32_t node, const LeafOwnership& owners) const {
    const unsigned n = owners.edge_begin(node + 1) - owners.edge_begin(node);
    return {values_.data() + offset_[3 * node + 1], stride(n), n};
  }
  Block faces(std::uint32_t node, const BvhTopology& bvh) const {
    const unsigned n = bvh.leaf_count(node);
    return {values_.data() + offset_[3 * node + 2], stride(n), n};
  }
  /// Leaf `node`'s own coarse volume (from its volume, which holds its features').
  const CoarseDop& leaf(std::uint32_t node) const { return leaf_[node]; }
  /// Vertex slot `slot`'s coarse volume (quantize_vertices()).
  const CoarseDop& vertex(std::uint32_t slot) const { return vertices_[slot]; }
  /// The merge of two coarse volumes (as quantizing the merge of the float ones: every
  /// rounding is monotone).
  static CoarseDop merged(const CoarseDop& a, const CoarseDop& b) {
    CoarseDop m;
    for (int k = 0; k < 16; ++k) {
      m.lo[k] = a.lo[k] < b.lo[k] ? a.lo[k] : b.lo[k];
      m.hi[k] = a.hi[k] > b.hi[k] ? a.hi[k] : b.hi[k];
    }
    return m;
  }

  std::size_t bytes() const {
    return values_.capacity() * sizeof(std::int16_t) + (leaf_.capacity() + vertices_.capacity()) * sizeof(CoarseDop) +
           offset_.capacity() * sizeof(std::uint32_t);
  }

 private:
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

  std::vector<std::uint32_t> offset_;  ///< per node: its vertex, edge and face block
  LargeVector<std::int16_t> values_;
  Grid grid_{};
  std::uint32_t epoch_ = 0;  ///< steps begun: a leaf's lanes are this step's when its stamp is 2 epoch_
  std::unique_ptr<std::atomic<std::uint32_t>[]> stamp_;  ///< per node: 2 e filled at step e, 2 e + 1 filling
  LargeVector<CoarseDop> leaf_;      ///< per node: a leaf's own coarse volume
  LargeVector<CoarseDop> vertices_;  ///< per vertex slot: its coarse volume
};

}  // namespace mccd::detail
