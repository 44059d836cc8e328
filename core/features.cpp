#include "core/features.h"

#include <algorithm>

namespace mccd {

namespace {

/// The faces sharing a vertex with face f0 (f0 included), ascending, into `out`.
void faces_near(const MeshTopology& topo, std::uint32_t f0, std::vector<std::uint32_t>& out) {
  out.clear();
  for (auto w : topo.faces()[f0]) out.insert(out.end(), topo.vertex_faces_begin(w), topo.vertex_faces_end(w));
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

/// The edges above `a` of the faces sharing a vertex with face f0, ascending, into `out`.
void edges_near(const MeshTopology& topo, std::uint32_t f0, std::uint32_t a, std::vector<std::uint32_t>& out) {
  out.clear();
  for (auto w : topo.faces()[f0])
    for (auto* g = topo.vertex_faces_begin(w); g != topo.vertex_faces_end(w); ++g)
      for (auto b : topo.face_edges(*g))
        if (b > a) out.push_back(b);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

bool share_vertex(const Edge& x, const Edge& y) { return x[0] == y[0] || x[0] == y[1] || x[1] == y[0] || x[1] == y[1]; }

}  // namespace

FeaturePairs::FeaturePairs(const MeshTopology& topo) : topo_(&topo) {
  const std::size_t nv = topo.num_vertices();
  first_face_.assign(nv, 0);
  for (std::size_t v = 0; v < nv; ++v)
    if (topo.vertex_face_count(v)) first_face_[v] = *topo.vertex_faces_begin(v);
  first_face_of_edge_.resize(topo.num_edges());
  for (std::size_t e = 0; e < topo.num_edges(); ++e) first_face_of_edge_[e] = *topo.edge_faces_begin(e);
  std::vector<std::uint32_t> candidates;
  // VF: an orphan face f is adjacent to every face around v, in particular to the first one
  // (f0), so it is among the faces around f0's corners.
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (topo.vertex_face_count(v) == 0) continue;
    faces_near(topo, *topo.vertex_faces_begin(v), candidates);
    for (auto f : candidates) {
      const Triangle& tf = topo.faces()[f];
      if (tf[0] == v || tf[1] == v || tf[2] == v) continue;
      bool all_adjacent = true;
      for (auto* g = topo.vertex_faces_begin(v); g != topo.vertex_faces_end(v) && all_adjacent; ++g)
        all_adjacent = topo.adjacent(*g, f);
      if (all_adjacent) orphan_vf_.emplace_back(v, f);
    }
  }
  // EE: every face around b is adjacent to the first face around a, so b is an edge of a
  // face around one of that face's corners.
  for (std::uint32_t a = 0; a < topo.num_edges(); ++a) {
    const Edge& ea = topo.edges()[a];
    edges_near(topo, *topo.edge_faces_begin(a), a, candidates);
    for (auto b : candidates) {
      if (share_vertex(ea, topo.edges()[b])) continue;
      bool all_adjacent = true;
      for (auto* f = topo.edge_faces_begin(a); f != topo.edge_faces_end(a) && all_adjacent; ++f)
        for (auto* g = topo.edge_faces_begin(b); g != topo.edge_faces_end(b) && all_adjacent; ++g)
          all_adjacent = topo.adjacent(*f, *g);
      if (all_adjacent) orphan_ee_.emplace_back(a, b);
    }
  }
}

StaticOrphanCounts static_orphan_counts(const MeshTopology& topo) {
  StaticOrphanCounts c;
  std::vector<std::uint32_t> candidates;
  // VF: v's assigned face f0 is adjacent to f (and v not a corner of f).
  for (std::uint32_t v = 0; v < topo.num_vertices(); ++v) {
    if (topo.vertex_face_count(v) == 0) continue;
    faces_near(topo, *topo.vertex_faces_begin(v), candidates);
    for (auto f : candidates) {
      const Triangle& t = topo.faces()[f];
      if (t[0] != v && t[1] != v && t[2] != v) ++c.vf;
    }
  }
  // EE: the assigned faces of a and b (a < b, no shared vertex) are adjacent.
  for (std::uint32_t a = 0; a < topo.num_edges(); ++a) {
    const std::uint32_t fa = *topo.edge_faces_begin(a);
    const Edge& ea = topo.edges()[a];
    edges_near(topo, fa, a, candidates);
    for (auto b : candidates) {
      if (share_vertex(ea, topo.edges()[b])) continue;
      if (topo.adjacent(fa, *topo.edge_faces_begin(b))) ++c.ee;
    }
  }
  return c;
}

}  // namespace mccd
