#pragma once
/// @file What the fuzz targets check on accepted input; a failed check aborts (a finding).
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <mccd/geometry/mesh.h>

#define MCCD_FUZZ_CHECK(cond)                                                      \
  do {                                                                             \
    if (!(cond)) {                                                                 \
      std::fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
      std::abort();                                                                \
    }                                                                              \
  } while (0)

namespace mccd::fuzz {

/// An accepted mesh: every index in range, no repeated corner, finite coordinates.
inline void check_mesh(const TriMesh& m) {
  const std::size_t nv = m.num_vertices();
  for (const Triangle& t : m.faces) {
    MCCD_FUZZ_CHECK(t[0] < nv && t[1] < nv && t[2] < nv);
    MCCD_FUZZ_CHECK(t[0] != t[1] && t[1] != t[2] && t[0] != t[2]);
  }
  for (double v : m.vertices.xyz()) MCCD_FUZZ_CHECK(std::isfinite(v));
}

}  // namespace mccd::fuzz
