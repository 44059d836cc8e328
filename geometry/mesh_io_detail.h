#pragma once
/// @file Internal: what the mesh writers share.
#include <string>

#include <mccd/geometry/mesh.h>

namespace mccd::detail {

/// Throws mccd::Error "<path>: cannot write: face f: vertex index v out of range" before a
/// writer creates anything.
void check_writable_indices(const std::string& path, const TriMesh& mesh);

}  // namespace mccd::detail
