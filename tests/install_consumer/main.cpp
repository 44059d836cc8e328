// Built against the installed package: uses the public headers and the library.
#include <mccd/geometry/mesh.h>

#include <iostream>

int main() {
  mccd::TriMesh grid = mccd::make_grid_mesh(2);  // 9 vertices, 8 triangles, 16 edges
  mccd::validate_mesh(grid);
  mccd::MeshTopology topo(grid.num_vertices(), grid.faces);
  std::cout << "faces " << topo.num_faces() << " edges " << topo.num_edges() << "\n";
  return topo.num_faces() == 8 && topo.num_edges() == 16 ? 0 : 1;
}
