#pragma once
/// @file What the `mccd` renderer draws: meshes at some positions, with highlighted triangles.
#include <cstdint>
#include <string>
#include <vector>

#include <mccd/geometry/mesh.h>

namespace mccd::cli {

/// One mesh to draw: its triangles, its positions, and one flag per triangle (1: highlighted).
struct ViewMesh {
  std::string name;  ///< what the legend calls it ("cloth"; a file's path; "" for "mesh M")
  std::vector<Triangle> faces;
  Positions positions;
  std::vector<std::uint8_t> highlight;  ///< one per face
};

}  // namespace mccd::cli
