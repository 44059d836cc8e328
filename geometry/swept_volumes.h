#pragma once
/// @file Internal: the swept volumes of one step, per vertex, edge and face, over the whole step
/// and over its quarters, for one bounding-volume type.
///
/// A vertex moves on a segment from x0 to x1. Its quarter volumes bound the straight paths
/// between the computed points a + (k/4)(b - a), k = 0..4, inflated (see update_vertices) so
/// that each contains the exact part of the segment in [q/4, (q+1)/4]; its whole-step volume
/// is the merge of its four quarter volumes. An edge's and a face's volumes (whole or per
/// quarter) are the merges of their vertices'. A contact at time t lies in both features'
/// volumes of every quarter holding t, so two features can only meet in the quarters where
/// their quarter volumes overlap.
///
/// Consistency invariant that makes every method return identical contacts: a feature pair
/// reaches the elementary test only when its features' quarter volumes overlap in some
/// quarter (core/feature_tests.h). Every quarter volume lies inside the feature's whole-step
/// volume, hence inside the volume of every triangle around the feature and of every BVH node
/// above it, so whenever that test passes every carrier of the pair and all its ancestors
/// overlap, and every method reaches the pair. Whole-step tests and masks of quarters from
/// larger volumes (`within`) are implied by the quarter test, so they only save work.
///
/// Stored: per vertex its whole-step volume and its quarters, per edge its quarters, per face
/// its whole-step volume (what the BVH refits from). A face's quarters are merged when needed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <mccd/geometry/kdop.h>
#include <mccd/geometry/quarter_volumes.h>
#include <mccd/geometry/topology.h>

namespace mccd::detail {

template <BoundingVolume BV>
class SweptVolumes {
 public:
  using Quarters = QuarterVolume<BV>;

  void resize(const MeshTopology& topo) {
    vertex_.resize(topo.num_vertices());
    vertex_quarters_.resize(topo.num_vertices());
    edge_quarters_.resize(topo.num_edges());
    face_.resize(topo.num_faces());
  }

  /// Vertices [begin, end): their swept segments between the interleaved positions x0, x1,
  /// inflated by `min_distance`. Each range writes only its own vertices.
  void update_vertices(const double* x0, const double* x1, double min_distance, std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v != end; ++v) {
      const Vec3 a(x0[3 * v], x0[3 * v + 1], x0[3 * v + 2]);
      const Vec3 b(x1[3 * v], x1[3 * v + 1], x1[3 * v + 2]);
      // The split points and their projections carry rounding errors relative to the
      // coordinates (not to the projections), so each quarter is inflated by 2^-48 of the
      // largest coordinate, far above those errors, on top of the outward float rounding.
      // Each point is projected and rounded once; the volumes are merges of those.
      const Vec3 step = b - a;
      const Vec3 pts[5] = {a, a + 0.25 * step, a + 0.5 * step, a + 0.75 * step, b};
      BV at[5];
      for (int k = 0; k < 5; ++k) {
        at[k] = BV::empty();
        at[k].add_point(pts[k]);
      }
      const double margin = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()) * 0x1p-48 + min_distance;
      Quarters& q = vertex_quarters_[v];
      for (int k = 0; k < 4; ++k) {
        BV piece = BV::merged(at[k], at[k + 1]);
        piece.inflate(margin);
        q.set(k, piece);
      }
      vertex_[v] = q.whole();
    }
  }

  /// Faces [begin, end): the merge of their corners' volumes (after update_vertices).
  void update_faces(const MeshTopology& topo, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f != end; ++f) {
      const Triangle& t = topo.faces()[f];
      BV d = BV::merged(vertex_[t[0]], vertex_[t[1]]);
      d.merge(vertex_[t[2]]);
      face_[f] = d;
    }
  }

  /// Edges [begin, end): the merge of their two vertices' quarters (after update_vertices).
  void update_edges(const MeshTopology& topo, std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e != end; ++e) {
      const Edge& ed = topo.edges()[e];
      edge_quarters_[e] = Quarters::merged(vertex_quarters_[ed[0]], vertex_quarters_[ed[1]]);
    }
  }

  const BV& vertex(std::uint32_t v) const { return vertex_[v]; }
  const BV& face(std::uint32_t f) const { return face_[f]; }
  /// An edge's whole-step volume (merged on demand).
  BV edge(const Edge& e) const { return BV::merged(vertex_[e[0]], vertex_[e[1]]); }

  const Quarters& vertex_quarters(std::uint32_t v) const { return vertex_quarters_[v]; }
  const Quarters& edge_quarters(std::uint32_t e) const { return edge_quarters_[e]; }
  /// A face's quarters (merged on demand from its corners').
  Quarters face_quarters(const Triangle& t) const {
    Quarters q = Quarters::merged(vertex_quarters_[t[0]], vertex_quarters_[t[1]]);
    q.merge(vertex_quarters_[t[2]]);
    return q;
  }

 private:
  std::vector<BV> vertex_;                  ///< per vertex: the merge of its quarters
  std::vector<Quarters> vertex_quarters_;   ///< per vertex: its path over the quarters
  std::vector<Quarters> edge_quarters_;     ///< per edge: merge of its two vertices' quarters
  std::vector<BV> face_;                    ///< per face: merge of its three vertex volumes
};

}  // namespace mccd::detail
