// cloth-ball: a square cloth dropped onto a ball, which starts turning once the cloth has
// settled on it, so the cloth, held by friction, twists and curls around it (the paper's
// cloth-ball benchmark, figure 17, simulated here with position-based dynamics).
#include <cmath>
#include <numbers>

#include "fixtures/shapes.h"
#include "generators/generators.h"
#include "generators/meshes.h"
#include "generators/pbd_cloth.h"
#include "generators/random.h"

namespace mccd::gen {

nlohmann::json cloth_ball_parameters(SceneSize size) {
  // quads per side, ball rings, frames; the simulated time is the same at every size
  const int n = size == SceneSize::Full ? 210 : size == SceneSize::Small ? 40 : 12;
  const int rings = size == SceneSize::Full ? 32 : size == SceneSize::Small ? 12 : 6;
  const int frames = size == SceneSize::Full ? 100 : size == SceneSize::Small ? 20 : 6;
  return {{"quads_per_side", n},  {"ball_rings", rings},   {"frames", frames},       {"duration_s", 3.3},
          {"substep_s", 1.0 / 480}, {"cloth_side", 2.0},   {"ball_radius", 0.5},      {"drop_height", 0.08},
          {"spin_start_s", 1.0},   {"spin_rad_per_s", 1.5}, {"friction", 0.6},        {"bend", 0.01},
          {"thickness_per_edge", 0.5}};
}

void run_cloth_ball(const nlohmann::json& p, std::uint64_t seed, const FrameSink& sink) {
  const int n = p.at("quads_per_side"), rings = p.at("ball_rings"), frames = p.at("frames");
  const double side = p.at("cloth_side"), radius = p.at("ball_radius"), friction = p.at("friction");
  const double spin_start = p.at("spin_start_s"), spin_rate = p.at("spin_rad_per_s");
  Rng rng(seed);

  // the cloth, turned and shifted a little by the seed, just above the ball
  TriMesh cloth = make_grid_mesh(n, side);
  const double turn = rng.uniform(0, std::numbers::pi / 2);
  const Vec3 shift(rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), radius + double(p.at("drop_height")));
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(turn, Vec3::UnitZ()).toRotationMatrix();
  for (std::size_t i = 0; i < cloth.num_vertices(); ++i) cloth.vertices.set_point(i, rot * cloth.vertices.point(i) + shift);

  const double edge = side / n, thickness = double(p.at("thickness_per_edge")) * edge;
  PbdCloth::Options opt;
  opt.bend = p.at("bend");
  opt.repulsion = thickness;
  PbdCloth sim(cloth, opt);

  const TriMesh ball_rest = make_uv_sphere(rings, 2 * rings, radius);
  TriMesh scene = cloth;
  scene.name = "cloth-ball";
  const std::size_t ball_first = append_piece(scene, ball_rest);

  const SubstepTiming timing = substep_timing(p);  // plain names: clang 14 cannot capture bindings
  const int substeps = timing.substeps;
  const double dt = timing.dt;
  double t = 0, angle = 0, omega = 0;
  // the ball: a sphere of the mesh's radius, turning about z; friction drags the cloth along
  const double contact_r = radius + 0.5 * thickness;
  const PbdCloth::Collider collide = [&](Vec3& q, const Vec3& x) {
    const double d = q.norm();
    if (d >= contact_r || d == 0) return;
    const Vec3 normal = q / d;
    q = contact_r * normal;
    const Vec3 surface_motion = dt * omega * Vec3(-x.y(), x.x(), 0);
    Vec3 slip = (q - x) - surface_motion;
    slip -= slip.dot(normal) * normal;
    q -= friction * slip;
  };
  for (int f = 0; f < frames; ++f) {
    if (f > 0)
      for (int s = 0; s < substeps; ++s) {
        t += dt;
        omega = t < spin_start ? 0.0 : spin_rate * std::min(1.0, (t - spin_start) / 0.3);
        angle += omega * dt;
        sim.substep(dt, collide);
      }
    sim.write(scene.vertices, 0);
    place_turned(scene, ball_first, ball_rest, angle);
    sink(f, scene);
  }
}

}  // namespace mccd::gen
