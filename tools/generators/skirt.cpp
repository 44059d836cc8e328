// skirt: a dancer's body turning one way and back, wearing a skirt of three flared, ruffled
// layers pinned at the waist (PBD cloth). The skirt swings out, wraps around the legs when
// the turn reverses and folds onto itself, layer against layer (the paper's Princess and
// Flamenco kind of load, figures 14-15).
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "generators/generators.h"
#include "generators/meshes.h"
#include "generators/pbd_cloth.h"
#include "generators/random.h"

namespace mccd::gen {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr int kLayers = 3;
constexpr double kWaistZ = 1.05, kWaistR = 0.16;

struct Capsule {
  Vec3 a, b;  // in the body's frame
  double r;
};
// hips and torso, two legs (the head is in the mesh only: the skirt never reaches it)
const std::array<Capsule, 3> kBody{{{{0, 0, 0.95}, {0, 0, 1.45}, 0.14},
                                    {{0.09, 0, 0.1}, {0.09, 0, 0.9}, 0.065},
                                    {{-0.09, 0, 0.1}, {-0.09, 0, 0.9}, 0.065}}};

TriMesh make_body(int segments) {
  TriMesh body;
  for (const Capsule& c : kBody) {
    TriMesh part = make_capsule(segments, segments / 4, segments / 3, c.r, c.a.z(), c.b.z());
    for (std::size_t i = 0; i < part.num_vertices(); ++i) part.vertices.set_point(i, part.vertices.point(i) + Vec3(c.a.x(), 0, 0));
    append_piece(body, part);
  }
  TriMesh head = make_uv_sphere(segments / 2, segments, 0.1);
  for (std::size_t i = 0; i < head.num_vertices(); ++i) head.vertices.set_point(i, head.vertices.point(i) + Vec3(0, 0, 1.68));
  append_piece(body, head);
  return body;
}

}  // namespace

nlohmann::json skirt_parameters(SceneSize size) {
  const int segments = size == SceneSize::Full ? 180 : size == SceneSize::Small ? 60 : 16;
  const int rows = size == SceneSize::Full ? 40 : size == SceneSize::Small ? 14 : 4;
  const int frames = size == SceneSize::Full ? 100 : size == SceneSize::Small ? 20 : 6;
  return {{"segments", segments}, {"rows", rows},         {"frames", frames},       {"duration_s", 3.3},
          {"substep_s", 1.0 / 480}, {"body_segments", size == SceneSize::Full ? 24 : 12},
          {"turn_rad", 2.0},      {"turn_period_s", 2.2}, {"flare_rad", 0.35},      {"ruffle", 0.04},
          {"layer_gap", 0.015},   {"friction", 0.3},      {"bend", 0.02}};
}

void run_skirt(const nlohmann::json& p, std::uint64_t seed, const FrameSink& sink) {
  const int segments = p.at("segments"), rows = p.at("rows"), frames = p.at("frames");
  const double flare = p.at("flare_rad"), ruffle = p.at("ruffle"), gap = p.at("layer_gap"), friction = p.at("friction");
  Rng rng(seed);
  TriMesh skirt;
  std::vector<std::size_t> pinned;
  for (int layer = 0; layer < kLayers; ++layer) {
    // the inner layer is the longest; each layer has its own ruffle count and phase
    const double length = (0.85 - 0.15 * layer) * rng.uniform(0.95, 1.05), top = kWaistR + gap * layer;
    const int waves = 16 + 5 * layer;
    const double phase = rng.uniform(0, 2 * kPi);
    const TriMesh tube = make_tube(rows, segments, [&](int row, int s) {
      const double down = length * row / rows, a = 2 * kPi * s / segments;
      const double r = top + down * std::sin(flare) + ruffle * std::pow(down / length, 1.5) * std::sin(waves * a + phase);
      return Vec3(r * std::cos(a), r * std::sin(a), kWaistZ - down * std::cos(flare));
    });
    const std::size_t first = append_piece(skirt, tube);
    for (int s = 0; s < segments; ++s) pinned.push_back(first + s);
  }
  const double edge = 2 * kPi * kWaistR / segments;
  PbdCloth::Options opt;
  opt.bend = p.at("bend");
  opt.repulsion = std::max(0.8 * gap, 0.6 * edge);
  PbdCloth sim(skirt, opt);
  for (std::size_t i : pinned) sim.pin(i);

  const TriMesh body_rest = make_body(p.at("body_segments"));
  TriMesh scene = skirt;
  scene.name = "skirt";
  const std::size_t body_first = append_piece(scene, body_rest);

  const SubstepTiming timing = substep_timing(p);  // plain names: clang 14 cannot capture bindings
  const int substeps = timing.substeps;
  const double dt = timing.dt;
  const double turn = double(p.at("turn_rad")) * rng.uniform(0.9, 1.1), period = p.at("turn_period_s");
  auto angle_at = [&](double t) { return turn * std::sin(2 * kPi * t / period); };
  double angle = 0, omega = 0;
  const double thickness = opt.repulsion;
  // the body's capsules, turned by `angle`; friction drags the cloth with the body's surface
  const PbdCloth::Collider collide = [&](Vec3& q, const Vec3& x) {
    const Eigen::Matrix3d to_body = Eigen::AngleAxisd(-angle, Vec3::UnitZ()).toRotationMatrix();
    for (const Capsule& c : kBody) {
      const Vec3 local = to_body * q, axis = c.b - c.a;
      const double u = std::clamp((local - c.a).dot(axis) / axis.squaredNorm(), 0.0, 1.0);
      const Vec3 off = local - (c.a + u * axis);
      const double d = off.norm(), reach = c.r + thickness;
      if (d >= reach || d == 0) continue;
      const Vec3 normal = to_body.transpose() * (off / d);
      q += (reach - d) * normal;
      Vec3 slip = (q - x) - dt * omega * Vec3(-x.y(), x.x(), 0);
      slip -= slip.dot(normal) * normal;
      q -= friction * slip;
    }
  };
  double t = 0;
  for (int f = 0; f < frames; ++f) {
    if (f > 0)
      for (int s = 0; s < substeps; ++s) {
        t += dt;
        const double next = angle_at(t);
        omega = (next - angle) / dt;
        angle = next;
        const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix();
        for (std::size_t i : pinned) sim.set_target(i, r * skirt.vertices.point(i));
        sim.substep(dt, collide);
      }
    sim.write(scene.vertices, 0);
    place_turned(scene, body_first, body_rest, angle);
    sink(f, scene);
  }
}

}  // namespace mccd::gen
