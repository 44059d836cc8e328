// `mccd demo`: a cloth dropped onto a ball, simulated on the spot (fixtures/drape.h), run
// through the same engine as `mccd run`, with the summary and a picture of the step two fifths
// of the way through, when the cloth wraps the ball.
#include <memory>

#include <CLI/App.hpp>

#include "command.h"
#include "fixtures/drape.h"
#include "options.h"
#include "run_driver.h"
#include "run_input.h"
#include "run_options.h"

namespace {

using namespace mccd;
using namespace mccd::cli;

/// The step the picture shows without --image-step: two fifths of the way through.
std::size_t picture_step(int frames) { return std::size_t(frames - 1) * 2 / 5; }

struct DemoArgs {
  int size = 40, frames = 45;
  RunSettings settings;
};

int demo(DemoArgs& a) {
  // the simulation runs on the demo's threads
  const RunInput in =
      input_from_generated([&] { return make_cloth_on_ball(a.size, std::max(6, a.size / 2), a.frames); },
                           a.settings.threads, "demo: a cloth dropped onto a ball");
  std::printf("a cloth of %zu triangles dropped onto a ball of %zu triangles, simulated for %d frames\n",
              in.meshes[0].num_faces(), in.meshes[1].num_faces(), a.frames);
  a.settings.up = Vec3(0, 0, 1);  // the simulation's gravity is along -z
  a.settings.exit_zero = true;  // the demo is meant to find contacts
  // the picture: two fifths of the way through, when the cloth wraps the ball (the help says so)
  if (!a.settings.image_step) a.settings.image_step = picture_step(a.frames);
  return run_frames(in, a.settings, "mccd demo");
}

const Command reg("demo", "drop a cloth onto a ball, find every collision, and draw them (demo.png)", 10,
                  [](CLI::App& app) -> Runner {
                    auto a = std::make_shared<DemoArgs>();
                    a->settings.image = "demo.png";
                    const std::string about =
                        "Simulates a square cloth falling onto a ball (a few thousand triangles), then finds every "
                        "collision frame by frame as 'mccd run' does: the cloth's triangles rest on the ball's "
                        "surface and the ball's vertices poke through them. Prints the table and the summary and "
                        "draws the picture (demo.png, or --image) of step (frames - 1) * 2 / 5, two fifths of the "
                        "way through (step " + std::to_string(picture_step(DemoArgs{}.frames)) + " of the default " +
                        std::to_string(DemoArgs{}.frames) + " frames), when the cloth wraps the ball: at its first "
                        "contact, or its start if it has none; --image-step K draws step K instead.";
                    app.add_option("--size", a->size, "cloth resolution: N x N quads, 10 to 200 (default 40)")
                        ->type_name("N")
                        ->check(integer_in(10, 200));
                    app.add_option("--frames", a->frames, "frames simulated, at 30 per second, 2 to 300 (default 45)")
                        ->type_name("N")
                        ->check(integer_in(2, 300));
                    add_method_option(app, a->settings.scene.method);
                    add_threads_option(app, a->settings.threads);
                    add_picture_options(app, a->settings,
                                        "step (frames - 1) * 2 / 5, two fifths of the way through (its first "
                                        "contact, else its start)",
                                        "demo.png");
                    add_display_options(app, a->settings);
                    app.footer(about + "\n\nExit status: 0 when it ran, 2 usage error.");
                    return [a] { return demo(*a); };
                  });

}  // namespace
