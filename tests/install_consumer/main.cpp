// Built against the installed package: only the public headers, beside the host's own
// core/contact.h and geometry/mesh.h (host_include/, first on the include path).
#include "core/contact.h"     // the host's
#include "geometry/mesh.h"    // the host's

#include <mccd/parallel/scene.h>
#include <mccd/geometry/topology.h>

#include <cstdio>

int main() {
  const host::Contact hc;
  const host::Mesh hm;
  // a 2 x 2 grid of quads in z = 0 (9 vertices, 8 triangles, 16 edges)
  mccd::TriMesh grid;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) grid.vertices.xyz().insert(grid.vertices.xyz().end(), {0.5 * i - 0.5, 0.5 * j - 0.5, 0.0});
  for (std::uint32_t j = 0; j < 2; ++j)
    for (std::uint32_t i = 0; i < 2; ++i) {
      const std::uint32_t a = 3 * j + i, b = a + 1, c = a + 3, d = c + 1;
      grid.faces.push_back({a, b, d});
      grid.faces.push_back({a, d, c});
    }
  mccd::MeshTopology topo(grid.num_vertices(), grid.faces);

  // a second, small triangle falling through the grid's middle
  mccd::TriMesh drop;
  drop.vertices = {{0.1, 0.3, 0.5}, {0.2, 0.3, 0.9}, {0.1, 0.4, 0.9}};  // clear of the grid's edges
  drop.faces = {{0, 1, 2}};
  mccd::Scene scene({grid, drop});
  mccd::Positions next = drop.vertices;
  next.mat().col(2).array() -= 0.8;  // corner 0 crosses z = 0 at t = 0.625
  mccd::StepResult r = scene.advance(std::vector<mccd::PositionsView>{grid.vertices, next});
  std::printf("faces %zu edges %zu contacts %zu earliest %.3f host %d %d\n", topo.num_faces(), topo.num_edges(),
              r.contacts.size(), r.earliest_toi, hc.id, hm.triangles);
  return topo.num_faces() == 8 && topo.num_edges() == 16 && r.contacts.size() == 1 ? 0 : 1;
}
