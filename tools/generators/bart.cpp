// bart: unconnected triangles of mixed sizes crowded into a box, each drifting on its own
// smooth random path, tumbling and wobbling (the paper's BART benchmark, figure 18: mostly
// unstructured motion, many overlapping primitives, high depth complexity). A procedural
// animation: positions are a closed-form function of time.
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>

#include "generators/generators.h"
#include "generators/random.h"

namespace mccd::gen {

nlohmann::json bart_parameters(SceneSize size) {
  const int triangles = size == SceneSize::Full ? 4000 : size == SceneSize::Small ? 1000 : 100;
  const int frames = size == SceneSize::Full ? 100 : size == SceneSize::Small ? 20 : 6;
  return {{"triangles", triangles}, {"frames", frames},    {"duration_s", 3.3},
          {"box_half_side", 0.5 * std::cbrt(triangles / 4000.0)},
          {"min_size", 0.05},       {"max_size", 0.25},    {"drift", 0.15},
          {"max_rate", 3.0},        {"wobble", 0.2}};
}

namespace {

struct Mover {
  Vec3 centre;
  std::array<Vec3, 3> amplitude, corner;  // drift amplitudes; corners about the centre
  std::array<double, 3> rate, phase;      // drift terms
  Vec3 axis;
  double spin, wobble_rate;
  std::array<double, 3> wobble_phase;
};

}  // namespace

void run_bart(const nlohmann::json& p, std::uint64_t seed, const FrameSink& sink) {
  const int count = p.at("triangles"), frames = p.at("frames");
  const double half = p.at("box_half_side"), drift = p.at("drift"), max_rate = p.at("max_rate"), wobble = p.at("wobble");
  const double lo = std::log(double(p.at("min_size"))), hi = std::log(double(p.at("max_size")));
  Rng rng(seed);
  std::vector<Mover> movers(count);
  TriMesh scene;
  scene.name = "bart";
  scene.vertices.resize(3 * std::size_t(count));
  for (int t = 0; t < count; ++t) {
    Mover& m = movers[t];
    m.centre = rng.in_box(Vec3::Constant(-half), Vec3::Constant(half));
    const double size = std::exp(rng.uniform(lo, hi));
    for (int k = 0; k < 3; ++k) {
      m.amplitude[k] = rng.uniform(0, drift) * rng.unit_vector();
      m.rate[k] = rng.uniform(0.3, max_rate);
      m.phase[k] = rng.uniform(0, 2 * std::numbers::pi);
      m.corner[k] = size * rng.uniform(0.4, 1.0) * rng.unit_vector();
      m.wobble_phase[k] = rng.uniform(0, 2 * std::numbers::pi);
    }
    m.axis = rng.unit_vector();
    m.spin = rng.uniform(-max_rate, max_rate);
    m.wobble_rate = rng.uniform(0.5, max_rate);
    const auto v = std::uint32_t(3 * t);
    scene.faces.push_back({v, v + 1, v + 2});
  }
  const double frame_dt = double(p.at("duration_s")) / frames;
  for (int f = 0; f < frames; ++f) {
    const double time = f * frame_dt;
    for (int t = 0; t < count; ++t) {
      const Mover& m = movers[t];
      Vec3 c = m.centre;
      for (int k = 0; k < 3; ++k) c += std::sin(m.rate[k] * time + m.phase[k]) * m.amplitude[k];
      const Eigen::Matrix3d r = Eigen::AngleAxisd(m.spin * time, m.axis).toRotationMatrix();
      for (int k = 0; k < 3; ++k) {
        const double grow = 1 + wobble * std::sin(m.wobble_rate * time + m.wobble_phase[k]);
        scene.vertices.set_point(3 * std::size_t(t) + k, c + grow * (r * m.corner[k]));
      }
    }
    sink(f, scene);
  }
}

}  // namespace mccd::gen
