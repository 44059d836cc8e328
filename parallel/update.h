#pragma once
/// @file Internal: stage 1 of a step (parallel/stepper.cpp), the update: the step's positions
/// become swept volumes per vertex (geometry/swept_volumes.h; edges' and faces' are merged
/// from them where needed) and, under the leaf rule, coarse volumes on the step's grid. Loops
/// over chunks dealt out as threads free up (fixed work per item, but a busy virtual machine
/// stalls a thread now and then: a static partition made the stage wait for it).
#include <algorithm>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include <oneapi/tbb/partitioner.h>

#include <mccd/core/leaf_lanes.h>
#include <mccd/core/scene_topology.h>
#include <mccd/core/stats.h>
#include <mccd/core/unchanged_leaves.h>
#include <mccd/geometry/assert.h>
#include <mccd/geometry/mesh.h>
#include <mccd/geometry/swept_volumes.h>
#include <mccd/parallel/tbb_executor.h>

namespace mccd::detail {

/// Vertices per chunk of the update's loops: a 256th of the scene's, from 256 to 2048 (a small
/// scene still gives 16 threads several chunks each; a large one keeps its chunks long, and
/// its longest chunk stays a small part of the step's critical path on 16 threads). A multiple
/// of 64: the vector kernel's groups of slots (SweptVolumes::update_vertex_slots_keeping).
inline std::size_t vertex_grain(std::size_t vertices) {
  return std::clamp<std::size_t>(vertices / 256, 256, 2048) / 64 * 64;
}

/// The volumes of every vertex (edges' and faces' are merged from their vertices' when
/// needed), in storage order (SweptVolumes::update_vertex_slots_keeping). `fixed` (per vertex
/// id; nullptr: none): the static meshes' vertices, whose volumes were computed once and are
/// kept. `track` (nullptr: none): every other vertex is noted there as it is read
/// (UnchangedLeaves::note), and those that repeat the previous step keep their volumes.
/// `lanes` (leaf rule; nullptr: none), begun on the step's grid: each slot's coarse volume
/// from its quarters while they are in cache; with `quantize_kept` false only the slots whose
/// volumes are computed (those of the kept ones still hold: LeafLanes::begin()).
template <BoundingVolume BV>
void update_swept_volumes(SweptVolumes<BV>& swept, const MeshTopology& topo, const Positions& x0,
                          const Positions& x1, double min_distance, const std::uint8_t* fixed = nullptr,
                          UnchangedLeaves* track = nullptr, LeafLanes<BV>* lanes = nullptr,
                          bool quantize_kept = true) {
  const double* a = x0.data();
  const double* b = x1.data();
  auto keep = [fixed, track, a, b](std::uint32_t v, std::size_t slot) {
    return (fixed && fixed[v]) || (track && track->note(slot, a + 3 * std::size_t(v), b + 3 * std::size_t(v)));
  };
  dynamic_for(topo.num_vertices(), vertex_grain(topo.num_vertices()), [&](std::size_t begin, std::size_t end) {
    if (lanes) {
      const CoarseOut coarse = lanes->coarse_out();
      swept.update_vertex_slots_keeping(
          a, b, min_distance, begin, end, keep,
          [&](std::size_t s, const QuarterVolume<BV>& q) { lanes->quantize_vertex(s, q); }, &coarse, quantize_kept);
    } else {
      swept.update_vertex_slots_keeping(a, b, min_distance, begin, end, keep,
                                        [](std::size_t, const QuarterVolume<BV>&) {});
    }
  });
}

/// The box of x0 and x1 together: each chunk of vertices' own box in parallel, then merged in
/// chunk order (the box one serial pass gives; a serial pass was most of the stage's span).
/// Chunks short enough that the longest is a small part of the stage's span on many threads.
inline Bounds3 step_bounds(const Positions& x0, const Positions& x1, std::vector<Bounds3>& chunks) {
  constexpr std::size_t kChunk = 2048;
  const std::size_t n = x0.rows(), nc = (n + kChunk - 1) / kChunk;
  chunks.resize(nc);
  for_each_index(
      nc,
      [&](std::size_t c) {
        const std::size_t b = c * kChunk, e = std::min(n, b + kChunk);
        const Bounds3 p = bounding_box(PositionsView(x0.data() + 3 * b, e - b));
        const Bounds3 q = bounding_box(PositionsView(x1.data() + 3 * b, e - b));
        chunks[c] = {p.min.cwiseMin(q.min), p.max.cwiseMax(q.max)};
      },
      tbb::simple_partitioner());
  constexpr double inf = std::numeric_limits<double>::infinity();
  Bounds3 box{Vec3::Constant(inf), Vec3::Constant(-inf)};
  for (const Bounds3& c : chunks) box = {box.min.cwiseMin(c.min), box.max.cwiseMax(c.max)};
  return box;
}

/// What the update reads and writes.
template <BoundingVolume BV>
struct UpdateState {
  SweptVolumes<BV> swept;  ///< per vertex, in the leaf rule's storage order
  LeafLanes<BV> lanes;     ///< leaf rule: the leaves' coarse volumes, filled as used
  GridKeeper<BV::kSlabs> grid;  ///< their grid, fitted to each step
  std::vector<Bounds3> chunk_bounds;  ///< step_bounds' scratch
  std::vector<std::uint8_t> fixed;   ///< per vertex id: of a static mesh (empty: none is)
};

/// Stage 1: the swept volumes of x0 -> x1 for the moving meshes. `track` (full steps under
/// the leaf rule; nullptr: none): each vertex's motion is noted as the update reads it, and the
/// volumes of those that repeat the previous step are kept (UnchangedLeaves::active()).
template <BoundingVolume BV>
void update_stage(const SceneTopology& scene, const Positions& x0, const Positions& x1, double min_distance,
                  UnchangedLeaves* track, UpdateState<BV>& state, StepStats& stats) {
  const MeshTopology& topo = scene.topology();
  MCCD_ASSERT(x0.rows() == topo.num_vertices() && x1.rows() == topo.num_vertices(), "positions not sized to the scene");
  const SceneTopology::Ranges& moving = scene.moving();
  // Leaf rule: every vertex's coarse volume on a grid that holds the step (the leaves' lanes
  // are filled from them when a leaf pair or the self stage first needs them). The grid is
  // fitted to the positions first, so the update's pass can quantize each volume it writes.
  // Where the grid is the last step's, the kept volumes' coarse volumes from then still hold.
  LeafLanes<BV>* lanes = nullptr;
  bool hold = false;
  if (!state.lanes.empty()) {
    const Bounds3 box = step_bounds(x0, x1, state.chunk_bounds);
    if (box.min.x() <= box.max.x()) hold = state.lanes.begin(state.grid.fit(box.min.data(), box.max.data()));
    lanes = &state.lanes;
  }
  update_swept_volumes(state.swept, topo, x0, x1, min_distance, state.fixed.empty() ? nullptr : state.fixed.data(),
                       track, lanes, !hold);
  if (lanes) lanes->vertices_done();
  for (const auto& [b, e] : moving.vertices) stats.updated_vertices += e - b;
}

}  // namespace mccd::detail
