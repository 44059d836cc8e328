#include <mccd/geometry/mesh.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <mccd/geometry/error.h>

namespace mccd {

void validate_mesh(const TriMesh& mesh) {
  const std::string name = mesh.name.empty() ? std::string("mesh") : mesh.name;
  const std::size_t nv = mesh.num_vertices();
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Triangle& t = mesh.faces[f];
    for (int k = 0; k < 3; ++k) {
      if (t[k] >= nv)
        throw Error(name + ": face " + std::to_string(f) + ": vertex index " + std::to_string(t[k]) +
                    " out of range [0, " + std::to_string(nv) + ")");
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      throw Error(name + ": face " + std::to_string(f) + ": repeated vertex index (" + std::to_string(t[0]) + ", " +
                  std::to_string(t[1]) + ", " + std::to_string(t[2]) + ")");
  }
  validate_positions(mesh.vertices, nv, name);
}

void validate_positions_shape(const PositionsView& positions, std::size_t num_vertices, const std::string& what) {
  if (positions.cols() != 3)
    throw Error(what + ": has " + std::to_string(positions.cols()) + " columns, expected 3 (x, y, z)");
  if (positions.rows() != num_vertices)
    throw Error(what + ": has " + std::to_string(positions.rows()) + " vertices, expected " +
                std::to_string(num_vertices));
  if (num_vertices > 0 && positions.data() == nullptr) throw Error(what + ": null position buffer");
}

void validate_positions(const PositionsView& positions, std::size_t num_vertices, const std::string& what) {
  validate_positions_shape(positions, num_vertices, what);
  for (std::size_t v = 0; v < positions.rows(); ++v)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(positions(v, c)))
        throw Error(what + ": vertex " + std::to_string(v) + ": coordinate " + "xyz"[c] + " is not finite (" +
                    std::to_string(positions(v, c)) + ")");
}

std::size_t count_zero_area_faces(const TriMesh& mesh) {
  std::size_t n = 0;
  for (const Triangle& t : mesh.faces) {
    const Vec3 a = mesh.vertices.point(t[0]), b = mesh.vertices.point(t[1]), c = mesh.vertices.point(t[2]);
    if ((b - a).cross(c - a).squaredNorm() == 0.0) ++n;
  }
  return n;
}

Bounds3 bounding_box(const PositionsView& positions) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Bounds3 b{Vec3::Constant(inf), Vec3::Constant(-inf)};
  if (positions.is_dense_double()) {  // one pass over the numbers, no conversion
    // 4 points' numbers at a time into 12 running bounds of their own (independent of each
    // other: vector lanes, no chain of dependent minima), then those by coordinate
    constexpr std::size_t kBlock = 12;
    const double* p = static_cast<const double*>(positions.data());
    const std::size_t m = 3 * positions.rows();
    double lo[kBlock], hi[kBlock];
    std::fill(lo, lo + kBlock, inf);
    std::fill(hi, hi + kBlock, -inf);
    std::size_t i = 0;
    for (; i + kBlock <= m; i += kBlock)
      for (std::size_t j = 0; j < kBlock; ++j) {
        lo[j] = std::min(lo[j], p[i + j]);
        hi[j] = std::max(hi[j], p[i + j]);
      }
    for (std::size_t j = 0; j < kBlock; ++j) {
      b.min[j % 3] = std::min(b.min[j % 3], lo[j]);
      b.max[j % 3] = std::max(b.max[j % 3], hi[j]);
    }
    for (; i < m; ++i) {  // i is a multiple of 3 here: the last points' coordinates in order
      b.min[i % 3] = std::min(b.min[i % 3], p[i]);
      b.max[i % 3] = std::max(b.max[i % 3], p[i]);
    }
    return b;
  }
  for (std::size_t v = 0; v < positions.rows(); ++v) {
    b.min = b.min.cwiseMin(positions.point(v));
    b.max = b.max.cwiseMax(positions.point(v));
  }
  return b;
}

}  // namespace mccd
