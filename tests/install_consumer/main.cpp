// Built against the installed package: uses the public headers and the library as the
// README shows.
#include <mccd/core/scene.h>
#include <mccd/geometry/mesh.h>

#include <cstdio>

int main() {
  mccd::TriMesh grid = mccd::make_grid_mesh(2);  // 9 vertices, 8 triangles, 16 edges
  mccd::MeshTopology topo(grid.num_vertices(), grid.faces);

  // a second, small triangle falling through the grid's middle
  mccd::TriMesh drop;
  drop.vertices.resize(3, 3);
  drop.vertices << 0.1, 0.3, 0.5, 0.2, 0.3, 0.9, 0.1, 0.4, 0.9;  // clear of the grid's edges
  drop.faces = {{0, 1, 2}};
  mccd::Scene scene({grid, drop});
  mccd::Positions next = drop.vertices;
  next.col(2).array() -= 0.8;  // corner 0 crosses z = 0 at t = 0.625
  mccd::StepResult r = scene.advance(std::vector<mccd::PositionsView>{grid.vertices, next});
  std::printf("faces %zu edges %zu contacts %zu earliest %.3f\n", topo.num_faces(), topo.num_edges(),
              r.contacts.size(), r.earliest_toi);
  return topo.num_faces() == 8 && topo.num_edges() == 16 && r.contacts.size() == 1 ? 0 : 1;
}
