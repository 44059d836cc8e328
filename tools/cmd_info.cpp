// `mccd info FILE...`: loads meshes and prints their size, connectivity and bounds.
#include <chrono>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include "args.h"
#include "command.h"
#include <mccd/geometry/mesh.h>
#include <mccd/geometry/mesh_io.h>
#include <mccd/geometry/topology.h>

namespace {

void print_info(const std::string& path) {
  const auto t0 = std::chrono::steady_clock::now();
  const mccd::TriMesh mesh = mccd::read_mesh(path);
  const auto t1 = std::chrono::steady_clock::now();
  const mccd::MeshTopology topo(mesh.num_vertices(), mesh.faces);
  const mccd::Bounds3 box = mccd::bounding_box(mesh.vertices);
  char bounds[256];
  std::snprintf(bounds, sizeof bounds, "[%.9g, %.9g, %.9g] .. [%.9g, %.9g, %.9g]", box.min.x(), box.min.y(),
                box.min.z(), box.max.x(), box.max.y(), box.max.z());
  std::cout << path << "\n"
            << "  vertices:            " << mesh.num_vertices() << "\n"
            << "  triangles:           " << mesh.num_faces() << "\n"
            << "  edges:               " << topo.num_edges() << "\n"
            << "  boundary edges:      " << topo.num_boundary_edges() << "\n"
            << "  non-manifold edges:  " << topo.num_nonmanifold_edges() << "\n"
            << "  zero-area triangles: " << mccd::count_zero_area_faces(mesh) << "\n"
            << "  bounding box:        " << bounds << "\n"
            << "  load time:           " << std::chrono::duration<double, std::milli>(t1 - t0).count() << " ms\n";
}

int info(const std::vector<std::string>& argv) {
  const mccd::cli::Args args(argv, {}, {});
  if (args.positional().empty()) throw mccd::Error("usage: mccd info FILE...");
  // Every file is reported; a file that fails does not stop the others, but the status is 2.
  int status = 0;
  for (const std::string& path : args.positional()) {
    try {
      print_info(path);
    } catch (const std::exception& e) {
      std::cout.flush();
      std::cerr << "mccd info: error: " << e.what() << "\n";
      status = 2;
    }
  }
  return status;
}

const mccd::cli::Command reg("info", "info FILE...",
                             "print vertex, triangle and edge counts, defects and bounds of mesh files (.ply, .obj)",
                             info);

}  // namespace
