// Carriers and orphans: every VF and EE pair that must be tested has exactly one carrier
// among the non-adjacent triangle pairs, or is in the orphan set, never both.
#include <mccd/core/canonical_rule_carriers.h>
#include <mccd/core/canonical_rule_orphans.h>

#include <gtest/gtest.h>

#include <set>

#include "fixtures/scenes.h"

using namespace mccd;
using namespace mccd::detail;

namespace {
void check_partition(const TriMesh& m) {
  MeshTopology topo(m.num_vertices(), m.faces);
  Carriers fp(topo);
  OrphanSet orphans(topo);
  std::set<std::pair<std::uint32_t, std::uint32_t>> ovf(orphans.vf().begin(), orphans.vf().end());
  std::set<std::pair<std::uint32_t, std::uint32_t>> oee(orphans.ee().begin(), orphans.ee().end());
  EXPECT_EQ(ovf.size(), orphans.vf().size());
  for (std::uint32_t v = 0; v < topo.num_vertices(); ++v)
    for (std::uint32_t f = 0; f < topo.num_faces(); ++f) {
      const Triangle& t = topo.faces()[f];
      if (t[0] == v || t[1] == v || t[2] == v) continue;
      int carriers = 0;
      for (auto* s = topo.vertex_faces_begin(v); s != topo.vertex_faces_end(v); ++s)
        if (!topo.adjacent(*s, f) && fp.carries_vf(v, *s, f)) ++carriers;
      ASSERT_EQ(carriers + int(ovf.count({v, f})), 1) << "VF " << v << " " << f;
    }
  for (std::uint32_t a = 0; a < topo.num_edges(); ++a)
    for (std::uint32_t b = a + 1; b < topo.num_edges(); ++b) {
      const Edge &ea = topo.edges()[a], &eb = topo.edges()[b];
      if (ea[0] == eb[0] || ea[0] == eb[1] || ea[1] == eb[0] || ea[1] == eb[1]) continue;
      int carriers = 0;
      for (auto s : topo.edge_faces(a))
        for (auto t : topo.edge_faces(b))
          if (!topo.adjacent(s, t) && fp.carries_ee(a, s, b, t)) ++carriers;
      ASSERT_EQ(carriers + int(oee.count({a, b})), 1) << "EE " << a << " " << b;
    }
}
}  // namespace

TEST(CarriersAndOrphans, GridPartition) { check_partition(make_grid_mesh(6)); }
TEST(CarriersAndOrphans, SpherePartition) { check_partition(make_sphere_mesh(6, 10)); }
TEST(CarriersAndOrphans, TubePartition) { check_partition(make_twisting_tube(8, 7, 2).meshes[0]); }

TEST(CarriersAndOrphans, NonManifoldFan) {
  // three triangles sharing one edge (0,1), plus a separate one touching at vertex 2
  TriMesh m;
  m.vertices.resize(7);
  m.vertices.mat().setRandom();
  m.faces = {{0, 1, 2}, {0, 1, 3}, {1, 0, 4}, {2, 5, 6}};
  check_partition(m);
}

TEST(CarriersAndOrphans, OrphansAreFewOnAGrid) {
  // Interior vertices of a regular grid: an orphan needs every face around v adjacent to f.
  TriMesh g = make_grid_mesh(20);
  MeshTopology topo(g.num_vertices(), g.faces);
  OrphanSet fp(topo);
  EXPECT_GT(fp.vf().size(), 0u);
  EXPECT_LT(fp.vf().size(), 2 * g.num_vertices());
  EXPECT_LT(fp.ee().size(), 2 * topo.num_edges());
}

TEST(CarriersAndOrphans, CanonicalOrphanSetIsNoLargerThanStatic) {
  // The canonical rule only orphans pairs with no non-adjacent carrier at all, a subset of
  // the pairs whose statically assigned triangles happen to be adjacent.
  for (const TriMesh& m : {make_grid_mesh(12), make_sphere_mesh(8, 12), make_twisting_tube(10, 9, 2).meshes[0]}) {
    MeshTopology topo(m.num_vertices(), m.faces);
    OrphanSet fp(topo);
    const StaticOrphanCounts st = static_orphan_counts(topo);
    EXPECT_LE(fp.vf().size(), st.vf);
    EXPECT_LE(fp.ee().size(), st.ee);
    EXPECT_GT(st.vf, fp.vf().size());  // and strictly smaller on these meshes
  }
}
