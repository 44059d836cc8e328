// `mccd info FILE...`: loads meshes and prints their size, connectivity and bounds.
// Exit status 2 when any file cannot be read (the others are still reported).
#include <chrono>
#include <cstdio>
#include <exception>
#include <iostream>
#include <memory>
#include <string>

#include <CLI/App.hpp>

#include "command.h"
#include "options.h"
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

int info(const std::vector<std::string>& paths) {
  // Every file is reported; a file that fails does not stop the others, but the status is 2.
  int status = mccd::cli::kExitClean;
  for (const std::string& path : paths) {
    try {
      print_info(path);
    } catch (const std::exception& e) {
      std::cout.flush();
      std::cerr << "mccd info: error: " << e.what() << "\n";
      status = mccd::cli::kExitUsage;
    }
  }
  return status;
}

const mccd::cli::Command reg("info", "print vertex, triangle and edge counts, defects and bounds of mesh files", 30,
                             [](CLI::App& app) -> mccd::cli::Runner {
                               auto paths = std::make_shared<std::vector<std::string>>();
                               app.add_option("FILE", *paths, "mesh files (.ply ascii or binary, .obj)")
                                   ->required()
                                   ->type_name("FILE");
                               app.footer("Prints per file: vertices, triangles, unique edges, boundary and "
                                          "non-manifold edges, zero-area triangles, bounding box, load time.\n"
                                          "Exit status: 0 every file read, 2 usage error or any file unreadable "
                                          "(the others are still reported).");
                               return [paths] { return info(*paths); };
                             });

}  // namespace
