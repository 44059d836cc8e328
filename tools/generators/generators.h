#pragma once
/// @file The benchmark scenes of the paper's evaluation (section 6.2), generated here from a
/// seed: `cloth-ball`, `n-body`, `bart` and `skirt`. Each generator is a simulation or a
/// procedural animation of one triangle mesh (all of a scene's objects in one mesh, as
/// disconnected pieces); the scene cache (scene_cache.h) writes its frames as PLY files.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <mccd/geometry/mesh.h>

namespace mccd::gen {

/// How big a generated scene is: `tiny` (a few hundred triangles, a few frames: unit tests),
/// `small` (a few thousand triangles: smoke runs), `full` (the paper's sizes, >= 90 frames).
enum class SceneSize { Tiny, Small, Full };
const char* to_string(SceneSize s);
/// Parses "tiny", "small" or "full"; throws mccd::Error naming the accepted values otherwise.
SceneSize parse_size(const std::string& name);

/// Receives each frame in order: `mesh` holds the triangles and that frame's positions.
using FrameSink = std::function<void(int frame, const TriMesh& mesh)>;

struct Generator {
  const char* name;
  /// Bumped whenever the generator's output changes, so cached frames of an older one are
  /// regenerated.
  int version;
  const char* description;
  /// The parameters of a size (resolution, frame count, time step...), as recorded in the
  /// scene cache's manifest; `frames` is always present.
  nlohmann::json (*parameters)(SceneSize size);
  /// Runs the generator with those parameters and seed, handing every frame to `sink`.
  void (*run)(const nlohmann::json& parameters, std::uint64_t seed, const FrameSink& sink);
};

/// Every generator, in the order of the paper's benchmark list.
const std::vector<Generator>& generators();
/// The generator called `name`; throws mccd::Error naming the known scenes otherwise.
const Generator& find_generator(const std::string& name);

/// The simulation's time step: `substeps` per frame of `dt` seconds each, from the parameters
/// duration_s (simulated time), frames and substep_s (the longest sub-step allowed).
struct SubstepTiming {
  int substeps;
  double dt;
};
SubstepTiming substep_timing(const nlohmann::json& parameters);

// The generators themselves (one file each).
nlohmann::json cloth_ball_parameters(SceneSize size);
void run_cloth_ball(const nlohmann::json& p, std::uint64_t seed, const FrameSink& sink);
nlohmann::json n_body_parameters(SceneSize size);
void run_n_body(const nlohmann::json& p, std::uint64_t seed, const FrameSink& sink);
nlohmann::json bart_parameters(SceneSize size);
void run_bart(const nlohmann::json& p, std::uint64_t seed, const FrameSink& sink);
nlohmann::json skirt_parameters(SceneSize size);
void run_skirt(const nlohmann::json& p, std::uint64_t seed, const FrameSink& sink);

}  // namespace mccd::gen
