// n-body: rigid spheres and cones in a closed box under gentle gravity, bouncing off each
// other and the walls (the paper's N-body benchmark, figure 16). Each body collides as a
// sphere a little smaller than its mesh, so touching bodies overlap slightly and their
// triangles really meet; impacts exchange momentum and set the bodies spinning.
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "generators/generators.h"
#include "generators/meshes.h"
#include "generators/random.h"

namespace mccd::gen {

nlohmann::json n_body_parameters(SceneSize size) {
  const int each = size == SceneSize::Full ? 120 : size == SceneSize::Small ? 12 : 3;
  const int rings = size == SceneSize::Full ? 8 : size == SceneSize::Small ? 6 : 4;
  const int frames = size == SceneSize::Full ? 100 : size == SceneSize::Small ? 20 : 6;
  // the box shrinks with the body count so the packing stays the same
  const double box = std::cbrt(each / 120.0);
  return {{"spheres", each},  {"cones", each},         {"sphere_rings", rings}, {"cone_segments", 4 * rings},
          {"frames", frames}, {"duration_s", 3.3},     {"substep_s", 1.0 / 240}, {"box_half_side", box},
          {"gravity", 3.0},   {"restitution", 0.85},   {"collision_scale", 0.92}, {"speed", 1.5}};
}

namespace {

struct Body {
  std::size_t first, count;  // the body's vertices in the scene mesh
  double radius, bound, inv_mass;  // collision sphere (a little smaller than the mesh), bounding sphere
  Vec3 c, v, omega;
  Eigen::Quaterniond q;
};

}  // namespace

void run_n_body(const nlohmann::json& p, std::uint64_t seed, const FrameSink& sink) {
  const int spheres = p.at("spheres"), cones = p.at("cones"), rings = p.at("sphere_rings"), frames = p.at("frames");
  const double half = p.at("box_half_side"), e = p.at("restitution"), scale = p.at("collision_scale");
  Rng rng(seed);
  TriMesh scene, local;  // local: every body's mesh about its own centre
  scene.name = "n-body";
  std::vector<Body> bodies;
  for (int b = 0; b < spheres + cones; ++b) {
    const bool sphere = b < spheres;
    TriMesh piece;
    double bound;
    if (sphere) {
      bound = rng.uniform(0.07, 0.11);
      piece = make_uv_sphere(rings, 2 * rings, bound);
    } else {
      const double r = rng.uniform(0.06, 0.09), h = rng.uniform(0.15, 0.22);
      bound = std::sqrt(r * r + h * h / 4);
      piece = make_cone(p.at("cone_segments"), r, h);
    }
    Body body{append_piece(local, piece), piece.num_vertices(), scale * bound, bound, 1.0 / std::pow(bound, 3), {}, {}, {}, {}};
    // a free place in the box (a few tries; an overlap left over is pushed apart by the solver)
    for (int attempt = 0; attempt < 100; ++attempt) {
      body.c = rng.in_box(Vec3::Constant(-half + bound), Vec3::Constant(half - bound));
      bool free = true;
      for (const Body& o : bodies) free = free && (o.c - body.c).norm() > o.radius + body.radius;
      if (free) break;
    }
    body.v = double(p.at("speed")) * rng.unit_vector();
    body.omega = rng.uniform(0, 4) * rng.unit_vector();
    body.q = Eigen::Quaterniond(Eigen::AngleAxisd(rng.uniform(0, 6.3), rng.unit_vector()));
    bodies.push_back(body);
  }
  scene.faces = local.faces;
  scene.vertices.resize(local.num_vertices());

  const SubstepTiming timing = substep_timing(p);  // plain names: clang 14 cannot capture bindings
  const int substeps = timing.substeps;
  const double dt = timing.dt;
  const Vec3 gravity(0, 0, -double(p.at("gravity")));
  // the walls hold each body's whole mesh (its bounding sphere) inside the box
  auto walls = [&](Body& b) {
    for (int k = 0; k < 3; ++k) {
      if (b.c[k] - b.bound < -half) b.c[k] = -half + b.bound, b.v[k] = e * std::abs(b.v[k]);
      if (b.c[k] + b.bound > half) b.c[k] = half - b.bound, b.v[k] = -e * std::abs(b.v[k]);
    }
  };
  auto substep = [&] {
    for (Body& b : bodies) {
      b.v += dt * gravity;
      b.c += dt * b.v;
      const double w = b.omega.norm();
      if (w > 0) b.q = (Eigen::Quaterniond(Eigen::AngleAxisd(w * dt, b.omega / w)) * b.q).normalized();
    }
    for (std::size_t i = 0; i < bodies.size(); ++i)
      for (std::size_t j = i + 1; j < bodies.size(); ++j) {
        Body &a = bodies[i], &b = bodies[j];
        const Vec3 d = b.c - a.c;
        const double dist = d.norm(), overlap = a.radius + b.radius - dist;
        if (overlap <= 0 || dist == 0) continue;
        const Vec3 n = d / dist;
        const double wsum = a.inv_mass + b.inv_mass;
        a.c -= (overlap * a.inv_mass / wsum) * n;
        b.c += (overlap * b.inv_mass / wsum) * n;
        const Vec3 rel = b.v - a.v;
        const double vn = rel.dot(n);
        if (vn >= 0) continue;
        const double impulse = -(1 + e) * vn / wsum;
        a.v -= impulse * a.inv_mass * n;
        b.v += impulse * b.inv_mass * n;
        const Vec3 slide = rel - vn * n;  // the sliding part sets both spinning
        a.omega += (0.4 / a.radius) * n.cross(slide);
        b.omega += (0.4 / b.radius) * n.cross(slide);
      }
    for (Body& b : bodies) walls(b);
  };
  for (int f = 0; f < frames; ++f) {
    if (f > 0)
      for (int s = 0; s < substeps; ++s) substep();
    for (const Body& b : bodies) {
      const Eigen::Matrix3d r = b.q.toRotationMatrix();
      for (std::size_t i = b.first; i < b.first + b.count; ++i) scene.vertices.set_point(i, r * local.vertices.point(i) + b.c);
    }
    sink(f, scene);
  }
}

}  // namespace mccd::gen
