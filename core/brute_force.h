#pragma once
/// @file Internal: the brute-force method, the oracle of the tests. Every VF pair (v not a
/// corner of f) and every EE pair sharing no vertex, found by sweep and prune along the widest
/// slab of the scene, then the same feature test as every other method (core/feature_tests.h),
/// so all methods report identical contacts.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/core/scene_topology.h>
#include <mccd/core/worker_output.h>
#include <mccd/geometry/large_allocator.h>
#include <mccd/geometry/swept_volumes.h>

namespace mccd::detail {

template <BoundingVolume BV, class NodeVolume, class FeatureTests>
void brute_force(const SceneTopology& scene, const BvhTopology& bvh, const LargeVector<NodeVolume>& nodes,
                 const SweptVolumes<BV>& swept, const FeatureTests& tests, WorkerOutput& out) {
  const MeshTopology& topo = scene.topology();
  const bool filter = scene.has_skipped_pairs();
  // sweep along the slab where the scene is widest (fewest overlapping intervals)
  int ax = 0;
  if (bvh.size() > 0) {
    const BV root = nodes[0].whole();
    float best = -1;
    for (int k = 0; k < 3; ++k)
      if (root.hi[k] - root.lo[k] > best) best = root.hi[k] - root.lo[k], ax = k;
  }
  // VF: faces sorted by lower bound; each vertex scans the faces whose interval can reach it.
  std::vector<std::pair<double, std::uint32_t>> faces(topo.num_faces());
  double max_face_extent = 0;  // the widest face along the sweep axis
  for (std::uint32_t f = 0; f < faces.size(); ++f) {
    const BV& vf = swept.face(f);
    faces[f] = {vf.lo[ax], f};
    max_face_extent = std::max(max_face_extent, double(vf.hi[ax]) - double(vf.lo[ax]));
  }
  std::sort(faces.begin(), faces.end());
  for (std::uint32_t v = 0; v < topo.num_vertices(); ++v) {
    if (topo.vertex_face_count(v) == 0) continue;
    const BV& vv = swept.vertex(v);
    // A face reaching the vertex has lo <= vv.hi and lo >= vv.lo - extent; the margin only
    // widens the scan (the full volume test decides).
    const double key = double(vv.lo[ax]) - max_face_extent * (1 + 1e-6) - 1e-30;
    auto it = std::lower_bound(faces.begin(), faces.end(), std::make_pair(key, 0u));
    for (; it != faces.end() && it->first <= double(vv.hi[ax]); ++it) {
      const std::uint32_t f = it->second;
      const Triangle& t = topo.faces()[f];
      if (t[0] == v || t[1] == v || t[2] == v) continue;
      if (filter && scene.skips(scene.mesh_of_vertex(v), scene.mesh_of_face(f))) continue;
      ++out.stats.volume_tests;
      if (!vv.overlaps(swept.face(f))) continue;
      tests.test_vf(v, f, out);
    }
  }
  // EE: classic sweep over edges sorted by lower bound.
  std::vector<BV> edge_volume(topo.num_edges());
  for (std::uint32_t e = 0; e < edge_volume.size(); ++e) edge_volume[e] = swept.edge(topo.edges()[e]);
  std::vector<std::pair<float, std::uint32_t>> edges(topo.num_edges());
  for (std::uint32_t e = 0; e < edges.size(); ++e) edges[e] = {edge_volume[e].lo[ax], e};
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const std::uint32_t a = edges[i].second;
    const Edge& ea = topo.edges()[a];
    const BV& va = edge_volume[a];
    for (std::size_t j = i + 1; j < edges.size() && edges[j].first <= va.hi[ax]; ++j) {
      const std::uint32_t b = edges[j].second;
      const Edge& eb = topo.edges()[b];
      if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
      if (filter && scene.skips(scene.mesh_of_edge(a), scene.mesh_of_edge(b))) continue;
      ++out.stats.volume_tests;
      if (!va.overlaps(edge_volume[b])) continue;
      tests.test_ee(a, b, out);
    }
  }
}

}  // namespace mccd::detail
