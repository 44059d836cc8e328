#pragma once
/// @file Internal: the swept volumes of a step (geometry/swept_volumes.h), vertices first, then
/// faces and edges, each under a static partition (fixed work per item); ranges below one
/// grain run serially, without a task.
#include <cstddef>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>

#include <mccd/geometry/swept_volumes.h>

namespace mccd::detail {

template <class Body>
void static_for(std::size_t n, std::size_t grain, const Body& body) {
  if (n <= grain) {
    if (n) body(std::size_t(0), n);
    return;
  }
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, grain),
      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); }, tbb::static_partitioner());
}

template <BoundingVolume BV>
void update_swept_volumes(SweptVolumes<BV>& swept, const MeshTopology& topo, const Positions& x0,
                          const Positions& x1, double min_distance) {
  constexpr std::size_t kGrain = 4096;
  static_for(topo.num_vertices(), kGrain, [&](std::size_t b, std::size_t e) {
    swept.update_vertices(x0.data(), x1.data(), min_distance, b, e);
  });
  static_for(topo.num_faces(), kGrain, [&](std::size_t b, std::size_t e) { swept.update_faces(topo, b, e); });
  static_for(topo.num_edges(), kGrain, [&](std::size_t b, std::size_t e) { swept.update_edges(topo, b, e); });
}

}  // namespace mccd::detail
