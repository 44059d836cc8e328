#include <mccd/core/canonical_rule_orphans.h>

#include <algorithm>

namespace mccd::detail {

namespace {

/// Collects the faces (or edges) near a face without duplicates: a stamp per element marks
/// those already taken in the current round, so no sorting is needed. Unordered.
class NearCollector {
 public:
  explicit NearCollector(std::size_t n) : stamp_(n, 0) {}
  /// The faces sharing a vertex with face f0 (f0 included).
  const std::vector<std::uint32_t>& faces_near(const MeshTopology& topo, std::uint32_t f0) {
    begin();
    for (auto w : topo.faces()[f0])
      for (auto* g = topo.vertex_faces_begin(w); g != topo.vertex_faces_end(w); ++g) take(*g);
    return out_;
  }
  /// The edges above `a` of the faces sharing a vertex with face f0.
  const std::vector<std::uint32_t>& edges_near(const MeshTopology& topo, std::uint32_t f0, std::uint32_t a) {
    begin();
    for (auto w : topo.faces()[f0])
      for (auto* g = topo.vertex_faces_begin(w); g != topo.vertex_faces_end(w); ++g)
        for (auto b : topo.face_edges(*g))
          if (b > a) take(b);
    return out_;
  }

 private:
  void begin() {
    out_.clear();
    if (++round_ == 0) {  // wrapped: reset the stamps
      std::fill(stamp_.begin(), stamp_.end(), 0);
      round_ = 1;
    }
  }
  void take(std::uint32_t x) {
    if (stamp_[x] != round_) {
      stamp_[x] = round_;
      out_.push_back(x);
    }
  }
  std::vector<std::uint32_t> stamp_;
  std::uint32_t round_ = 0;
  std::vector<std::uint32_t> out_;
};

bool share_vertex(const Edge& x, const Edge& y) { return x[0] == y[0] || x[0] == y[1] || x[1] == y[0] || x[1] == y[1]; }

}  // namespace

OrphanSet::OrphanSet(const MeshTopology& topo) {
  const std::size_t nv = topo.num_vertices();
  NearCollector near_faces(topo.num_faces()), near_edges(topo.num_edges());
  // VF: an orphan face f is adjacent to every face around v, in particular to the first one
  // (f0), so it is among the faces around f0's corners.
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (topo.vertex_face_count(v) == 0) continue;
    for (auto f : near_faces.faces_near(topo, *topo.vertex_faces_begin(v))) {
      const Triangle& tf = topo.faces()[f];
      if (tf[0] == v || tf[1] == v || tf[2] == v) continue;
      bool all_adjacent = true;
      for (auto* g = topo.vertex_faces_begin(v); g != topo.vertex_faces_end(v) && all_adjacent; ++g)
        all_adjacent = topo.adjacent(*g, f);
      if (all_adjacent) vf_.emplace_back(v, f);
    }
  }
  // EE: every face around b is adjacent to the first face around a, so b is an edge of a
  // face around one of that face's corners.
  for (std::uint32_t a = 0; a < topo.num_edges(); ++a) {
    const Edge& ea = topo.edges()[a];
    for (auto b : near_edges.edges_near(topo, *topo.edge_faces_begin(a), a)) {
      if (share_vertex(ea, topo.edges()[b])) continue;
      bool all_adjacent = true;
      for (auto* f = topo.edge_faces_begin(a); f != topo.edge_faces_end(a) && all_adjacent; ++f)
        for (auto* g = topo.edge_faces_begin(b); g != topo.edge_faces_end(b) && all_adjacent; ++g)
          all_adjacent = topo.adjacent(*f, *g);
      if (all_adjacent) ee_.emplace_back(a, b);
    }
  }
  std::sort(vf_.begin(), vf_.end());  // candidates come unordered
  std::sort(ee_.begin(), ee_.end());
}

StaticOrphanCounts static_orphan_counts(const MeshTopology& topo) {
  StaticOrphanCounts c;
  NearCollector near_faces(topo.num_faces()), near_edges(topo.num_edges());
  // VF: v's assigned face f0 is adjacent to f (and v not a corner of f).
  for (std::uint32_t v = 0; v < topo.num_vertices(); ++v) {
    if (topo.vertex_face_count(v) == 0) continue;
    for (auto f : near_faces.faces_near(topo, *topo.vertex_faces_begin(v))) {
      const Triangle& t = topo.faces()[f];
      if (t[0] != v && t[1] != v && t[2] != v) ++c.vf;
    }
  }
  // EE: the assigned faces of a and b (a < b, no shared vertex) are adjacent.
  for (std::uint32_t a = 0; a < topo.num_edges(); ++a) {
    const std::uint32_t fa = *topo.edge_faces_begin(a);
    const Edge& ea = topo.edges()[a];
    for (auto b : near_edges.edges_near(topo, fa, a)) {
      if (share_vertex(ea, topo.edges()[b])) continue;
      if (topo.adjacent(fa, *topo.edge_faces_begin(b))) ++c.ee;
    }
  }
  return c;
}

}  // namespace mccd::detail
