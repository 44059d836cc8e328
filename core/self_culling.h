#pragma once
/// @file Internal: self-collision culling by normal cones and contours, certified exactly.
///
/// A patch of one mesh cannot touch itself during a step when, for one coordinate axis d,
///  1. every triangle of the patch, projected along d onto the other two coordinates, keeps one
///     strict orientation over the whole step (the d component of its normal has one sign at
///     every time: the three Bernstein coefficients of that quadratic, each certain of its sign
///     under a rounding-error bound), and
///  2. the patch's boundary, projected the same way, stays a simple closed curve over the whole
///     step (no two of its edges ever meet but two consecutive ones at their common vertex),
/// provided the patch is a topological disk (connected, edge- and vertex-manifold,
/// consistently oriented, one boundary cycle). At any time the projection is then a local
/// homeomorphism of the disk, orientation-preserving, whose boundary maps onto a simple closed
/// curve; by the degree argument every point of the plane has at most one preimage: the
/// projection is injective, so no two distinct points of the patch coincide, and no vertex
/// meets a face it is not a corner of, nor an edge one it shares no end with. The projections
/// along an axis need no arithmetic (a coordinate is dropped), so the only rounding is in the
/// orientation and contour tests, each of which is bounded.
///
/// Which BVH nodes' triangles form such disks, and their boundary cycles, depends only on
/// connectivity and is found once, bottom-up in parallel: per node, the directed edges of its
/// boundary and its Euler characteristic, from its children's (shared edges cancel; shared
/// vertices and edges lie on both boundaries). A node of one connected mesh component whose
/// boundary is one simple cycle and whose characteristic is 1 is a disk. Patches whose boundary
/// is long for their size (ragged ones) are not followed up the tree. Every step then
/// certifies top-down: the first disk node on each path from the root
/// whose triangles share an axis sign (condition 1, per triangle, combined up the tree) and
/// whose contour passes (condition 2) covers its subtree. A BVTT self node or pair node whose
/// nodes are both under one covered node holds only feature pairs of that patch: it is skipped,
/// and so is a covered leaf's own pairs. Culling is exact: it removes only pairs that cannot
/// touch, so contacts do not change (tests compare against brute force).
///
/// Closed surfaces (a BVH node whose triangles are a whole mesh component that is a closed,
/// regular, consistently oriented surface of Euler characteristic 2, a topological sphere) get
/// a second certificate, by central projection from a point c(t) moving linearly between the
/// means of the component's vertices at the two ends of the step:
///  1. every triangle (a, b, c) keeps one strict orientation seen from c(t) over the whole step
///     (det(b - a, c - a, c(t) - a), a cubic in t: its four Bernstein coefficients share a sign
///     with certainty under a rounding bound), all triangles the same, and
///  2. at the start, a ray from c(0) (towards a point inside the first triangle) enters
///     exactly one triangle's cone (each test's sign certain under its bound).
/// Then c(t) lies on no triangle, the central projection onto the unit sphere around c(t) is a
/// branched covering whose degree is constant over the step and, by 2, of magnitude 1 at the
/// start; by Riemann-Hurwitz (2 = 2 * 1 - branching) it has no branch point, so it is a
/// homeomorphism at every time: no two distinct points of the surface coincide. A deforming
/// star-shaped body (a soft ball, the spheres scene) is certified whole, including the pairs
/// across the cuts between the disks below it.
///
/// Not used with a minimum distance (injectivity says nothing about how close two parts come)
/// nor under the paper's canonical rule (its experiments stay as they were).
#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/core/executor.h>
#include <mccd/core/scene_topology.h>
#include <mccd/geometry/lane_masks.h>
#include <mccd/geometry/positions.h>

namespace mccd::detail {

class SelfCulling {
 public:
  static constexpr std::uint32_t kNone = 0xffffffffu;

  /// No node can be culled.
  SelfCulling() = default;
  /// Finds the disk nodes of `bvh` among the meshes with self-collision of `scene` (loops
  /// through `ex`).
  SelfCulling(const BvhTopology& bvh, const SceneTopology& scene, const Executor& ex = serial_executor());

  /// Whether any node is a disk or a closed surface (otherwise certify() has nothing to do).
  bool possible() const { return disks_ != 0 || !closed_.empty(); }
  std::size_t num_disks() const { return disks_; }

  /// Certifies the nodes for the step x0 -> x1 (global vertex ids); until end_step(), covered()
  /// answers for this step. Serial over the tree's top, parallel over its leaves.
  /// `ray_meets(node, origin, direction)`, when given: false only when the ray from `origin`
  /// along `direction` certainly meets no triangle of `node` at the start of the step (its
  /// volume is apart from the ray); it lets the closed-surface certificate skip subtrees.
  using RayMeets = std::function<bool(std::uint32_t, const Vec3&, const Vec3&)>;
  /// `repeats(node)`, when given: true only when every corner of the node's triangles has bit
  /// for bit the start and end positions it had in the previous call (and the node's volume is
  /// the one it had then); a closed surface that repeats keeps the outcome of its certificate
  /// from that call instead of computing it again (a body at rest given as deforming).
  using Repeats = std::function<bool(std::uint32_t)>;
  /// Loops through `ex`; the certificates do not depend on it. `leaf_corners` (nullptr: none):
  /// each triangle's corners in the BVH's leaf order (entry bvh.leaf_first(leaf) + k for
  /// bvh.leaf_triangles(leaf)[k]; LeafOwnership::face_corners), read instead of the mesh's
  /// faces through the leaves' triangle ids.
  void certify(const BvhTopology& bvh, const MeshTopology& topo, const Positions& x0, const Positions& x1,
               const Executor& ex = serial_executor(), const RayMeets& ray_meets = {},
               const Triangle* leaf_corners = nullptr, const Repeats& repeats = {});
  /// Nothing is covered (a step that does not cull: brute force, or culling off).
  void clear() { active_ = false; }

  /// Whether BVH node n lies under (or is) a node certified this step.
  bool covered(std::uint32_t n) const { return active_ && top_[n] != kNone; }
  /// Whether nodes a and b lie under one node certified this step (every feature pair between
  /// them is inside that patch).
  bool covers(std::uint32_t a, std::uint32_t b) const { return active_ && top_[a] != kNone && top_[a] == top_[b]; }
  /// Nodes certified this step (the topmost ones, each covering its subtree).
  std::uint64_t certified() const { return active_ ? certified_ : 0; }

  /// The boundary cycle of disk node n (vertex ids in order, the patch on the left when the
  /// mesh's faces are counter-clockwise), or an empty range when n is not a disk.
  const std::uint32_t* cycle_begin(std::uint32_t n) const { return cycle_.data() + cycle_offset_[n]; }
  const std::uint32_t* cycle_end(std::uint32_t n) const { return cycle_.data() + cycle_offset_[n + 1]; }
  bool disk(std::uint32_t n) const { return cycle_offset_[n + 1] != cycle_offset_[n]; }

  /// The signs a triangle keeps along each axis over a step, as bits (bit 2d: the d component
  /// of its normal positive at every time; bit 2d + 1: negative), each certain under its
  /// rounding bound. Exposed for the tests.
  /// Only the axes with a bit in `wanted` are looked at (the others' bits are 0).
  static unsigned normal_signs(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& a1, const Vec3& b1,
                               const Vec3& c1, unsigned wanted = 0x3F);
  /// normal_signs (every axis) of n triangles, corners[i] (vertex ids) at the interleaved
  /// positions x0 and x1, in the vector lanes of `lanes`: bits[i], normal_signs' values bit for
  /// bit at every SIMD level. Exposed for the tests.
  /// Returns the bits all n share (their and, 0x3F for none); `bits` may be nullptr.
  static unsigned normal_signs_in_lanes(const LaneKernels& lanes, const double* x0, const double* x1,
                                        const std::uint32_t (*corners)[3], std::size_t n, std::uint8_t* bits);
  /// The sign (+1, -1, or 0: not certain) that det(b - a, c - a, p - a) keeps over the step,
  /// every point moving linearly from its `0` to its `1` position. Exposed for the tests.
  static int star_sign(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p0, const Vec3& a1,
                       const Vec3& b1, const Vec3& c1, const Vec3& p1);
  /// star_sign of n triangles, corners[i] (vertex ids) at the interleaved positions x0 and x1,
  /// seen from m0 and m1 (3 doubles each), in the vector lanes of `lanes`: signs[i], star_sign's
  /// values bit for bit at every SIMD level. Exposed for the tests.
  static void star_signs(const LaneKernels& lanes, const double* x0, const double* x1,
                         const std::uint32_t (*corners)[3], std::size_t n, const double* m0, const double* m1,
                         std::int8_t* signs);
  /// Whether BVH node n is a closed surface (a candidate for the central-projection
  /// certificate).
  bool closed(std::uint32_t n) const { return std::binary_search(closed_.begin(), closed_.end(), n); }
  std::size_t num_closed() const { return closed_.size(); }

  /// Whether the closed polyline `cycle` (vertex ids), projected along axis d, stays simple
  /// over the step x0 -> x1. Exposed for the tests.
  static bool contour_simple(const std::uint32_t* begin, const std::uint32_t* end, unsigned axis, const Positions& x0,
                             const Positions& x1);

 private:
  std::vector<std::uint32_t> cycle_offset_;  ///< CSR over nodes; empty range: not a disk
  std::vector<std::uint32_t> cycle_;
  std::size_t disks_ = 0;
  std::vector<std::uint32_t> closed_;             ///< closed-surface nodes, ascending
  std::vector<std::uint32_t> closed_vertex_begin_, closed_vertices_;  ///< CSR over closed_: vertex ids
  std::vector<std::uint32_t> closed_above_;  ///< per node: index in closed_ of the closed node above, or kNone
  std::vector<std::uint8_t> closed_ok_;      ///< per index of closed_, this step: certified
  /// per index of closed_: the outcome of its certificate in the last call (kUnknown: not
  /// computed then)
  std::vector<std::uint8_t> closed_last_;
  static constexpr std::uint8_t kUnknown = 2;
  struct Backoff {
    int failures = 0, skip = 0;  ///< failures in a row; steps left without a try
  };
  std::vector<Backoff> closed_backoff_;  ///< per index of closed_
  void find_closed(const BvhTopology& bvh, const SceneTopology& scene, const std::vector<std::uint8_t>& regular,
                   const std::vector<std::uint32_t>& component);
  /// The central-projection certificate of closed_[k] for the step (`leaf_corners` as in
  /// certify()).
  bool certify_closed(std::size_t k, const BvhTopology& bvh, const MeshTopology& topo, const Positions& x0,
                      const Positions& x1, const Executor& ex, const RayMeets& ray_meets,
                      const Triangle* leaf_corners) const;
  std::vector<std::uint8_t> signs_;  ///< per node, this step: normal_signs of all its triangles
  std::vector<std::uint32_t> top_;   ///< per node, this step: the certified node above, or kNone
  std::vector<std::uint8_t> signed_;  ///< per node: its signs are needed (an inner disk above it)
  std::vector<std::uint32_t> sign_roots_;  ///< subtrees whose inner signs are combined in parallel
  std::vector<std::uint32_t> sign_top_;    ///< the nodes above them, descending
  std::uint32_t sign_cut_nodes_ = 0;       ///< the tree's size when they were found (0: not yet)
  std::uint64_t certified_ = 0;
  bool active_ = false;
};

}  // namespace mccd::detail
