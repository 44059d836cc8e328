#include <mccd/core/canonical_rule_carriers.h>

namespace mccd::detail {

Carriers::Carriers(const MeshTopology& topo) : topo_(&topo) {
  const std::size_t nv = topo.num_vertices();
  first_face_.assign(nv, 0);
  for (std::size_t v = 0; v < nv; ++v)
    if (topo.vertex_face_count(v)) first_face_[v] = *topo.vertex_faces_begin(v);
  first_face_of_edge_.resize(topo.num_edges());
  for (std::size_t e = 0; e < topo.num_edges(); ++e) first_face_of_edge_[e] = *topo.edge_faces_begin(e);
  firsts_.resize(topo.num_faces());
  for (std::size_t f = 0; f < topo.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      firsts_[f].corner[k] = first_face_[topo.faces()[f][k]];
      firsts_[f].edge[k] = first_face_of_edge_[topo.face_edges(f)[k]];
    }
}

}  // namespace mccd::detail
