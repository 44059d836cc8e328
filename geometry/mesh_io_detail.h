#pragma once
/// @file Internal: what the mesh readers and writers share.
#include <string>

#include <mccd/geometry/mesh.h>

namespace mccd::detail {

/// Throws mccd::Error "<path>: cannot write: face f: vertex index v out of range" before a
/// writer creates anything.
void check_writable_indices(const std::string& path, const TriMesh& mesh);

/// A mesh read from `path`: interleaved coordinates and triangles, validated (throws
/// mccd::Error naming the file).
TriMesh make_mesh(const std::string& path, std::vector<double> xyz, std::vector<Triangle> faces);

}  // namespace mccd::detail
