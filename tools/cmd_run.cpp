// `mccd run FRAMES...`: steps through frame files (or a built-in scene) and reports the
// contacts of every step; see run_driver.h for how, and `mccd run --help` for every option.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>

#include <CLI/App.hpp>

#include <mccd/geometry/error.h>
#include <mccd/geometry/mesh_io.h>

#include "command.h"
#include "mpi/cluster.h"
#include "options.h"
#include "run_driver.h"
#include "run_input.h"
#include "run_options.h"

namespace {

using namespace mccd;
using namespace mccd::cli;

struct RunArgs {
  std::vector<std::string> frames;
  std::string scene;
  int size = 4, frame_count = 31;
  RunSettings settings;
};

int run(RunArgs& a) {
  if (!a.scene.empty() && !a.frames.empty()) throw Error("give either frame files or --scene, not both");
  if (a.scene.empty() && a.frames.empty())
    throw Error("no frames given (files, a pattern like frame%03d.ply, or --scene NAME)");
  const RunInput input = a.scene.empty() ? input_from_files(a.frames)
                                         : input_from_scene(a.scene, a.size, a.frame_count, a.settings.threads);
  return run_frames(input, a.settings, "mccd run", nullptr, &cluster());
}

const Command reg(
    "run", "step through frames (files, a printf pattern, or a built-in scene) and report every collision", 20,
    [](CLI::App& app) -> Runner {
      auto a = std::make_shared<RunArgs>();
      const std::string about =
          "Steps frame k -> k+1 for every k (each vertex moving on a straight line) and reports every vertex-face "
          "and edge-edge pair that touches during the step, with its time of impact. Prints a table, one row per "
          "step: step k (frame k to k+1), VF and EE pairs in contact during the step (each pair once), the first "
          "impact in frame time (k + t, t in [0, 1]; with --substeps K, sub-step S's local time t is k + (S + t)/K), "
          "and the step's computation time; then a summary (steps, steps with contacts, contacts summed over steps, "
          "first impact and its step, time per step). A progress bar shows on a terminal (stderr).";
      app.add_option("FRAMES", a->frames,
                     "frame files (.ply, .obj; same triangles, moving vertices) in order, one printf pattern "
                     "such as 'frame%03d.ply' (frames from 0 or 1 up to the first gap), or one folder (its .ply "
                     "and .obj files in natural order: frame2 before frame10)")
          ->type_name("FILE");
      app.add_option("--scene", a->scene,
                     "a built-in scene instead of files: cloth (folding through itself), spheres, random, tube, "
                     "drape (a cloth dropped onto a ball)")
          ->type_name("NAME")
          ->check(CLI::IsMember({"cloth", "spheres", "random", "tube", "drape"}));
      app.add_option("--size", a->size, "built-in scene size in thousands of triangles, 1 to 200 (default 4)")
          ->type_name("K")
          ->check(integer_in(1, 200));
      app.add_option("--frames", a->frame_count,
                     "built-in scene frames, 2 to 5000 (default 31); --size times --frames at most " +
                         std::to_string(kMaxSizeTimesFrames))
          ->type_name("N")
          ->check(integer_in(2, 5000));
      add_engine_options(app, a->settings);
      add_file_options(app, a->settings);
      add_picture_options(app, a->settings,
                          "the first contact (the earliest impact of the first sub-step with contacts)", "");
      add_display_options(app, a->settings);
      app.footer(
          about + "\n\nExit status: 0 no collision, 1 collisions found (like diff or grep; --exit-zero gives 0), 2 usage or "
          "input error (the finished steps' files kept marked incomplete, or removed: --partial). SIGINT or SIGTERM "
          "stops at once, handling the files the same way.\n"
          "Example: mccd run 'cloth_%03d.ply' --contacts contacts.csv --stats stats.json --image first.png");
      return [a] { return run(*a); };
    });

}  // namespace
