#pragma once
/// @file Internal: the swept volumes of a step (geometry/swept_volumes.h): the vertices', a
/// parallel loop over chunks dealt out as threads free up (fixed work per item, but on a busy
/// virtual machine the host stalls one thread now and then: a static partition made the stage
/// wait for it); ranges below one grain run serially, without a task.
/// static_for (a static partition) serves the one-off loops of the set-up.
#include <cstddef>
#include <utility>
#include <vector>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>

#include <mccd/geometry/swept_volumes.h>

namespace mccd::detail {

/// body(begin, end) over chunks of about `grain` of [0, n) under `partitioner`; a range of at
/// most one grain runs on the calling thread, without a task.
template <class Body, class Partitioner>
void chunked_for(std::size_t n, std::size_t grain, const Body& body, const Partitioner& partitioner) {
  if (n <= grain) {
    if (n) body(std::size_t(0), n);
    return;
  }
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, grain),
      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); }, partitioner);
}

/// Chunks under a static partition (the set-up's one-off loops).
template <class Body>
void static_for(std::size_t n, std::size_t grain, const Body& body) {
  chunked_for(n, grain, body, tbb::static_partitioner());
}

/// Chunks dealt out dynamically: a thread that the host stalls (a busy virtual machine) leaves
/// its chunks to the others.
template <class Body>
void dynamic_for(std::size_t n, std::size_t grain, const Body& body) {
  chunked_for(n, grain, body, tbb::simple_partitioner());
}

using IndexRanges = std::vector<std::pair<std::size_t, std::size_t>>;

/// The volumes of the given vertex ranges (the moving meshes'; a static mesh's volumes are
/// computed once; edges' and faces' are merged from their vertices' when needed). `kept`: see
/// SweptVolumes::update_vertices.
template <BoundingVolume BV>
void update_swept_volumes(SweptVolumes<BV>& swept, const MeshTopology& topo, const Positions& x0,
                          const Positions& x1, double min_distance, const IndexRanges& vertices,
                          const std::uint8_t* kept = nullptr) {
  constexpr std::size_t kGrain = 2048;
  if (vertices.size() == 1 && vertices[0].first == 0 && vertices[0].second == topo.num_vertices()) {
    // Every mesh moves: in storage order (SweptVolumes::update_vertex_slots).
    dynamic_for(topo.num_vertices(), kGrain, [&](std::size_t b, std::size_t e) {
      swept.update_vertex_slots(x0.data(), x1.data(), min_distance, b, e, kept);
    });
    return;
  }
  // Plain copies of the range ends: clang before 16 cannot capture structured bindings.
  for (const auto& range : vertices) {
    const std::size_t b0 = range.first, e0 = range.second;
    static_for(e0 - b0, kGrain, [&](std::size_t b, std::size_t e) {
      swept.update_vertices(x0.data(), x1.data(), min_distance, b0 + b, b0 + e, kept);
    });
  }
}

}  // namespace mccd::detail
