#include "generators/meshes.h"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace mccd::gen {

namespace {
constexpr double kPi = std::numbers::pi;
}

TriMesh make_revolved_mesh(const std::vector<std::pair<double, double>>& profile, int segments, double top, double bottom) {
  TriMesh m;
  const auto rings = std::uint32_t(profile.size()), segs = std::uint32_t(segments);
  m.vertices.resize(2 + std::size_t(rings) * segs);
  m.vertices.set_point(0, Vec3(0, 0, top));
  for (std::uint32_t k = 0; k < rings; ++k)
    for (std::uint32_t s = 0; s < segs; ++s) {
      const double a = 2 * kPi * s / segs;
      m.vertices.set_point(1 + k * segs + s, Vec3(profile[k].first * std::cos(a), profile[k].first * std::sin(a), profile[k].second));
    }
  const std::uint32_t south = 1 + rings * segs;
  m.vertices.set_point(south, Vec3(0, 0, bottom));
  auto at = [&](std::uint32_t k, std::uint32_t s) { return 1 + k * segs + s % segs; };
  for (std::uint32_t s = 0; s < segs; ++s) m.faces.push_back({0, at(0, s), at(0, s + 1)});
  for (std::uint32_t k = 0; k + 1 < rings; ++k)
    for (std::uint32_t s = 0; s < segs; ++s) {
      m.faces.push_back({at(k, s), at(k + 1, s), at(k + 1, s + 1)});
      m.faces.push_back({at(k, s), at(k + 1, s + 1), at(k, s + 1)});
    }
  for (std::uint32_t s = 0; s < segs; ++s) m.faces.push_back({at(rings - 1, s), south, at(rings - 1, s + 1)});
  return m;
}

TriMesh make_uv_sphere(int rings, int segments, double r) {
  std::vector<std::pair<double, double>> profile;
  for (int k = 1; k < rings; ++k) profile.emplace_back(r * std::sin(kPi * k / rings), r * std::cos(kPi * k / rings));
  return make_revolved_mesh(profile, segments, r, -r);
}

TriMesh make_cone(int segments, double r, double h) {
  return make_revolved_mesh({{r, -h / 2}}, segments, h / 2, -h / 2);
}

TriMesh make_capsule(int segments, int cap_rings, int body_rings, double r, double z0, double z1) {
  std::vector<std::pair<double, double>> profile;
  for (int k = 1; k <= cap_rings; ++k) {
    const double a = 0.5 * kPi * k / cap_rings;  // from the top pole to the equator
    profile.emplace_back(r * std::sin(a), z1 + r * std::cos(a));
  }
  for (int k = 1; k < body_rings; ++k) profile.emplace_back(r, z1 - (z1 - z0) * k / body_rings);
  for (int k = 0; k < cap_rings; ++k) {
    const double a = 0.5 * kPi * k / cap_rings;
    profile.emplace_back(r * std::cos(a), z0 - r * std::sin(a));
  }
  return make_revolved_mesh(profile, segments, z1 + r, z0 - r);
}

TriMesh make_tube(int rows, int segments, const std::function<Vec3(int row, int s)>& at) {
  TriMesh m;
  const auto segs = std::uint32_t(segments);
  m.vertices.resize(std::size_t(rows + 1) * segs);
  for (int row = 0; row <= rows; ++row)
    for (int s = 0; s < segments; ++s) m.vertices.set_point(std::size_t(row) * segs + s, at(row, s));
  auto id = [&](std::uint32_t row, std::uint32_t s) { return row * segs + s % segs; };
  for (std::uint32_t row = 0; row < std::uint32_t(rows); ++row)
    for (std::uint32_t s = 0; s < segs; ++s) {
      m.faces.push_back({id(row, s), id(row + 1, s), id(row + 1, s + 1)});
      m.faces.push_back({id(row, s), id(row + 1, s + 1), id(row, s + 1)});
    }
  return m;
}

void place_turned(TriMesh& scene, std::size_t first, const TriMesh& piece, double angle) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix();
  for (std::size_t i = 0; i < piece.num_vertices(); ++i) scene.vertices.set_point(first + i, r * piece.vertices.point(i));
}

std::size_t append_piece(TriMesh& scene, const TriMesh& piece) {
  const std::size_t first = scene.num_vertices();
  scene.vertices.resize(first + piece.num_vertices());
  for (std::size_t i = 0; i < piece.num_vertices(); ++i) scene.vertices.set_point(first + i, piece.vertices.point(i));
  for (const Triangle& f : piece.faces)
    scene.faces.push_back({std::uint32_t(f[0] + first), std::uint32_t(f[1] + first), std::uint32_t(f[2] + first)});
  return first;
}

}  // namespace mccd::gen
