#include "core/scenes.h"

#include <cmath>
#include <numbers>
#include <random>

#include "geometry/error.h"

namespace mccd {

namespace {
constexpr double kPi = std::numbers::pi;
}

AnimatedScene make_folding_cloth(int n, int frames) {
  AnimatedScene s;
  s.name = "cloth";
  s.meshes.push_back(make_grid_mesh(n, 1.0));
  s.meshes[0].name = "cloth";
  const Positions& rest = s.meshes[0].vertices;
  for (int f = 0; f < frames; ++f) {
    // fold angle from 0 to a little past pi: the right half sweeps over and through the left
    const double theta = 1.15 * kPi * f / std::max(1, frames - 1);
    Positions p = rest;
    for (Eigen::Index v = 0; v < p.rows(); ++v) {
      const double x = rest(v, 0), y = rest(v, 1);
      const double ripple = 0.03 * std::sin(9 * y + 4 * x) + 0.02 * std::cos(7 * x);
      if (x > 0) {
        p(v, 0) = x * std::cos(theta);
        p(v, 2) = x * std::sin(theta) + ripple;
      } else {
        p(v, 2) = ripple;
      }
    }
    s.frames.push_back({p});
  }
  s.meshes[0].vertices = s.frames[0][0];
  return s;
}

AnimatedScene make_deforming_spheres(int count, int rings, int frames) {
  AnimatedScene s;
  s.name = "spheres";
  std::vector<Vec3> centres;
  for (int i = 0; i < count; ++i) {
    const double a = 2 * kPi * i / count;
    centres.emplace_back(1.6 * std::cos(a), 1.6 * std::sin(a), 0.1 * i);
    TriMesh m = make_sphere_mesh(rings, 2 * rings, 1.0, Vec3::Zero());
    m.name = "sphere" + std::to_string(i);
    s.meshes.push_back(std::move(m));
  }
  for (int f = 0; f < frames; ++f) {
    const double u = double(f) / std::max(1, frames - 1);
    std::vector<Positions> fr;
    for (int i = 0; i < count; ++i) {
      const Positions& unit = s.meshes[i].vertices;
      Positions p(unit.rows(), 3);
      // drift toward the middle, so neighbours overlap more and more, while pulsating
      const Vec3 c = centres[i] * (1.0 - 0.55 * u);
      for (Eigen::Index v = 0; v < unit.rows(); ++v) {
        const Vec3 d = unit.row(v).transpose();
        const double r = 1.0 + 0.15 * std::sin(6 * d.z() + 3 * d.x() + 5 * u + i) * std::sin(2 * kPi * u + i);
        p.row(v) = (c + r * d).transpose();
      }
      fr.push_back(std::move(p));
    }
    s.frames.push_back(std::move(fr));
  }
  for (int i = 0; i < count; ++i) s.meshes[i].vertices = s.frames[0][i];
  return s;
}

AnimatedScene make_random_triangles(int count, int frames, unsigned seed) {
  AnimatedScene s;
  s.name = "random";
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  TriMesh m;
  m.name = "triangles";
  m.vertices.resize(3 * count, 3);
  // box side chosen so triangles (size ~ box / count^(1/3) * 1.5) meet often
  const double side = 1.0, size = 0.6 * side / std::cbrt(double(count));
  std::vector<Vec3> vel(3 * count);
  for (int t = 0; t < count; ++t) {
    const Vec3 c(U(rng), U(rng), U(rng));
    const Vec3 v(U(rng), U(rng), U(rng));
    for (int k = 0; k < 3; ++k) {
      m.vertices.row(3 * t + k) = (side * c + size * Vec3(U(rng), U(rng), U(rng))).transpose();
      vel[3 * t + k] = 0.01 * v + 0.05 * size * Vec3(U(rng), U(rng), U(rng));
    }
    m.faces.push_back({std::uint32_t(3 * t), std::uint32_t(3 * t + 1), std::uint32_t(3 * t + 2)});
  }
  s.meshes.push_back(m);
  Positions p = m.vertices;
  for (int f = 0; f < frames; ++f) {
    s.frames.push_back({p});
    for (Eigen::Index v = 0; v < p.rows(); ++v) {
      p.row(v) += vel[v].transpose();
      for (int c = 0; c < 3; ++c)  // bounce off the box walls
        if (std::abs(p(v, c)) > 1.2 && p(v, c) * vel[v][c] > 0) vel[v][c] = -vel[v][c];
    }
  }
  return s;
}

AnimatedScene make_twisting_tube(int rings, int segments, int frames) {
  AnimatedScene s;
  s.name = "tube";
  TriMesh m;
  m.name = "tube";
  const int nv = rings * segments;
  m.vertices.resize(nv, 3);
  auto id = [&](int r, int k) { return std::uint32_t(r * segments + (k % segments)); };
  for (int r = 0; r + 1 < rings; ++r)
    for (int k = 0; k < segments; ++k) {
      m.faces.push_back({id(r, k), id(r + 1, k), id(r + 1, k + 1)});
      m.faces.push_back({id(r, k), id(r + 1, k + 1), id(r, k + 1)});
    }
  const double length = 4.0, radius = 0.25;
  for (int f = 0; f < frames; ++f) {
    const double u = double(f) / std::max(1, frames - 1);
    const double bend = 2.6 * kPi * u;   // total bend angle: the ends meet past 2 pi
    const double twist = 3 * kPi * u;    // total twist
    Positions p(nv, 3);
    for (int r = 0; r < rings; ++r) {
      const double a = double(r) / (rings - 1);  // 0..1 along the tube
      // centre line: straight when bend = 0, an arc of angle `bend` otherwise
      Vec3 c, tangent_normal;
      const double phi = bend * (a - 0.5);
      if (bend < 1e-9) {
        c = Vec3(length * (a - 0.5), 0, 0);
        tangent_normal = Vec3(0, 1, 0);
      } else {
        const double R = length / bend;
        c = Vec3(R * std::sin(phi), R * (1 - std::cos(phi)), 0);
        tangent_normal = Vec3(-std::sin(phi), std::cos(phi), 0);
      }
      for (int k = 0; k < segments; ++k) {
        const double ang = 2 * kPi * k / segments + twist * (a - 0.5);
        const double rr = radius * (1 + 0.2 * std::sin(3 * ang + 5 * a));
        p.row(r * segments + k) = (c + rr * (std::cos(ang) * tangent_normal + std::sin(ang) * Vec3(0, 0, 1))).transpose();
      }
    }
    s.frames.push_back({p});
  }
  m.vertices = s.frames[0][0];
  s.meshes.push_back(m);
  return s;
}

AnimatedScene make_scene(const std::string& name, int size_k, int frames) {
  if (size_k < 1) throw Error("scene size must be at least 1 (thousand triangles), got " + std::to_string(size_k));
  if (frames < 2) throw Error("a scene needs at least 2 frames, got " + std::to_string(frames));
  if (name == "cloth") return make_folding_cloth(std::max(2, int(std::lround(std::sqrt(size_k * 500.0)))), frames);
  if (name == "spheres") {
    const int rings = std::max(3, int(std::lround(std::sqrt(size_k * 1000.0 / 4 / 4))));
    return make_deforming_spheres(4, rings, frames);
  }
  if (name == "random") return make_random_triangles(size_k * 1000, frames);
  if (name == "tube") {
    const int segments = std::max(6, int(std::lround(std::sqrt(size_k * 1000.0 / 2 / 4))));
    return make_twisting_tube(4 * segments, segments, frames);
  }
  throw Error("unknown scene '" + name + "' (expected cloth, spheres, random or tube)");
}

}  // namespace mccd
