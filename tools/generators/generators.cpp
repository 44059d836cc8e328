#include "generators/generators.h"

#include <algorithm>
#include <cmath>

#include <mccd/geometry/error.h>

namespace mccd::gen {

const char* to_string(SceneSize s) {
  switch (s) {
    case SceneSize::Tiny: return "tiny";
    case SceneSize::Small: return "small";
    case SceneSize::Full: return "full";
  }
  return "?";
}

SceneSize parse_size(const std::string& name) {
  for (SceneSize s : {SceneSize::Tiny, SceneSize::Small, SceneSize::Full})
    if (name == to_string(s)) return s;
  throw Error("scene size '" + name + "': expected tiny, small or full");
}

SubstepTiming substep_timing(const nlohmann::json& p) {
  const double frame_dt = double(p.at("duration_s")) / int(p.at("frames"));
  const int substeps = std::max(1, int(std::lround(frame_dt / double(p.at("substep_s")))));
  return {substeps, frame_dt / substeps};
}

const std::vector<Generator>& generators() {
  static const std::vector<Generator> all{
      {"cloth-ball", 3, "a square cloth (PBD) dropping onto a turning ball and curling around it", cloth_ball_parameters,
       run_cloth_ball},
      {"n-body", 2, "hundreds of rigid spheres and cones bouncing off each other and the walls of a box", n_body_parameters,
       run_n_body},
      {"bart", 1, "unconnected triangles in unstructured random motion, high depth complexity", bart_parameters, run_bart},
      {"skirt", 1, "a layered, ruffled skirt (PBD) swirling around a turning body and folding onto itself",
       skirt_parameters, run_skirt},
  };
  return all;
}

const Generator& find_generator(const std::string& name) {
  std::string known;
  for (const Generator& g : generators()) {
    if (name == g.name) return g;
    known += std::string(known.empty() ? "" : ", ") + g.name;
  }
  throw Error("unknown scene '" + name + "': expected one of " + known);
}

}  // namespace mccd::gen
