#pragma once
/// @file Internal: the swept volumes of one step, per vertex, edge and face, over the whole step
/// and over its pieces in time, for one bounding-volume type.
///
/// A vertex moves on a segment from x0 to x1; its volume bounds that segment (inflated by the
/// minimum distance). A face's volume is the merge of its three vertex volumes and contains the
/// swept triangle; an edge's likewise. Time pieces: the quarters [q/4, (q+1)/4] of the step,
/// each bounding the straight path between two computed points. A contact at time t lies in
/// both features' volumes of every quarter holding t, so two features can only meet in the
/// quarters where their quarter volumes overlap (meeting_quarters). Halves tested first cost
/// more tests and memory than they save.
///
/// Consistency invariant that makes every method return identical contacts: every feature
/// pair reaches the elementary test only after the overlap of its *feature volumes* (merges
/// of the same per-vertex volumes that build the triangle and node volumes). A feature volume
/// is contained in the volume of every triangle around the feature and of every BVH node
/// above it, so whenever the feature test passes, every carrier pair and all its ancestors
/// overlap and every method reaches the pair. The piece tests are only consulted after the
/// whole-step volumes overlap, so they keep the invariant.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <mccd/geometry/kdop.h>
#include <mccd/geometry/topology.h>

namespace mccd::detail {

template <BoundingVolume BV>
using PieceVolumes = std::array<BV, 4>;

/// The quarters q of the step (bit q, 0..3) in which two features may meet (see the file
/// comment), 0 when they cannot meet at all, given `overlap(q)`: whether their volumes of
/// quarter q overlap; only the quarters in `within` are tested.
template <class Overlap>
inline unsigned meeting_quarters(const Overlap& overlap, unsigned within = 0xF) {
  unsigned mask = 0;
  for (int q = 0; q < 4; ++q)
    if ((within >> q & 1u) && overlap(q)) mask |= 1u << q;
  return mask;
}

/// The first quarter in which two features may meet, -1 when never (stops at the first).
template <class Overlap>
inline int first_meeting_quarter(const Overlap& overlap) {
  for (int q = 0; q < 4; ++q)
    if (overlap(q)) return q;
  return -1;
}

template <BoundingVolume BV>
inline PieceVolumes<BV> merged_pieces(const PieceVolumes<BV>& a, const PieceVolumes<BV>& b) {
  PieceVolumes<BV> m;
  for (int k = 0; k < 4; ++k) m[k] = BV::merged(a[k], b[k]);
  return m;
}

template <BoundingVolume BV>
class SweptVolumes {
 public:
  void resize(const MeshTopology& topo) {
    vertex_.resize(topo.num_vertices());
    vertex_pieces_.resize(topo.num_vertices());
    edge_.resize(topo.num_edges());
    face_.resize(topo.num_faces());
    face_pieces_.resize(topo.num_faces());
  }

  /// Vertices [begin, end): their swept segments between the interleaved positions x0, x1,
  /// inflated by `min_distance`. Each range writes only its own vertices.
  void update_vertices(const double* x0, const double* x1, double min_distance, std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v != end; ++v) {
      const Vec3 a(x0[3 * v], x0[3 * v + 1], x0[3 * v + 2]);
      const Vec3 b(x1[3 * v], x1[3 * v + 1], x1[3 * v + 2]);
      // Pieces of the path, between computed points a + (k/4) (b - a). Those points and their
      // projections carry rounding errors relative to the coordinates (not to the
      // projections), so each piece is inflated by 2^-48 of the largest coordinate, far above
      // those errors, on top of the outward float rounding. Each point is projected and
      // rounded once; the volumes are merges of those (the same bounds as adding the points).
      const Vec3 step = b - a;
      const Vec3 pts[5] = {a, a + 0.25 * step, a + 0.5 * step, a + 0.75 * step, b};
      BV at[5];
      for (int k = 0; k < 5; ++k) {
        at[k] = BV::empty();
        at[k].add_point(pts[k]);
      }
      BV d = BV::merged(at[0], at[4]);
      if (min_distance > 0) d.inflate(min_distance);
      vertex_[v] = d;
      const double margin = std::max(a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()) * 0x1p-48 + min_distance;
      PieceVolumes<BV>& p = vertex_pieces_[v];
      for (int q = 0; q < 4; ++q) {
        p[q] = BV::merged(at[q], at[q + 1]);
        p[q].inflate(margin);
      }
    }
  }

  /// Faces [begin, end): the merge of their corners' volumes and pieces (after
  /// update_vertices).
  void update_faces(const MeshTopology& topo, std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f != end; ++f) {
      const Triangle& t = topo.faces()[f];
      BV d = BV::merged(vertex_[t[0]], vertex_[t[1]]);
      d.merge(vertex_[t[2]]);
      face_[f] = d;
      PieceVolumes<BV> m = merged_pieces(vertex_pieces_[t[0]], vertex_pieces_[t[1]]);
      face_pieces_[f] = merged_pieces(m, vertex_pieces_[t[2]]);
    }
  }

  /// Edges [begin, end): the merge of their two vertex volumes (after update_vertices).
  void update_edges(const MeshTopology& topo, std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e != end; ++e) {
      const Edge& ed = topo.edges()[e];
      edge_[e] = BV::merged(vertex_[ed[0]], vertex_[ed[1]]);
    }
  }

  const BV& vertex(std::uint32_t v) const { return vertex_[v]; }
  const BV& edge(std::uint32_t e) const { return edge_[e]; }
  const BV& face(std::uint32_t f) const { return face_[f]; }
  const PieceVolumes<BV>& face_pieces(std::uint32_t f) const { return face_pieces_[f]; }
  const PieceVolumes<BV>& vertex_pieces(std::uint32_t v) const { return vertex_pieces_[v]; }

  /// Piece tests (see the file comment), only after the whole-step volumes overlap: the
  /// quarters in which the two may meet (a bit mask), or the first one (-1 when never).
  unsigned vertex_face_quarters(std::uint32_t v, std::uint32_t f, unsigned within = 0xF) const {
    const auto &a = vertex_pieces_[v], &b = face_pieces_[f];
    return meeting_quarters([&](int k) { return a[k].overlaps(b[k]); }, within);
  }
  unsigned faces_quarters(std::uint32_t s, std::uint32_t t, unsigned within = 0xF) const {
    const auto &a = face_pieces_[s], &b = face_pieces_[t];
    return meeting_quarters([&](int k) { return a[k].overlaps(b[k]); }, within);
  }

 private:
  std::vector<BV> vertex_;                        ///< per vertex: its swept segment
  std::vector<PieceVolumes<BV>> vertex_pieces_;   ///< per vertex: its path over the pieces
  std::vector<BV> edge_;                          ///< per edge: merge of its two vertex volumes
  std::vector<BV> face_;                          ///< per face: merge of its three vertex volumes
  std::vector<PieceVolumes<BV>> face_pieces_;     ///< per face: merge of its corners' pieces
};

}  // namespace mccd::detail
