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
    const double* p = static_cast<const double*>(positions.data());
    for (std::size_t v = 0, n = positions.rows(); v < n; ++v)
      for (int k = 0; k < 3; ++k) {
        b.min[k] = std::min(b.min[k], p[3 * v + k]);
        b.max[k] = std::max(b.max[k], p[3 * v + k]);
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
