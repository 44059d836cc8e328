// The simulator queries against a full step on a real scene (default: cloth-ball 92 -> 93):
// is_collision_free, earliest_impact and candidates beside step(), on the whole step and on
// a shorter one (the end pulled back towards the start, as a line search does), alternating,
// medians. The scene is built once and its front exists, as in a simulator's loop.
//   bench_queries [DIR] [--threads N] [--rounds K]
// DIR: a Time-of-Impact scene, DIR/frames/*.ply (default: the shared data's toi/cloth-ball).
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/frame_sequence.h>

#include "harness/cli.h"

using namespace mccd;
using namespace mccd::bench;

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
double seconds(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

int main(int argc, char** argv) {
  std::string dir = std::string(MCCD_DEFAULT_DATA_DIR) + "/toi/cloth-ball";
  int threads = 1, rounds = 5;
  CLI::App app{"Times the simulator queries (is_collision_free, earliest_impact, candidates) beside a full step on a\n"
               "real scene, on the whole step and on shorter ones, alternating; prints the medians.",
               "bench_queries"};
  app.add_option("DIR", dir, "Time-of-Impact scene folder with frames/*.ply (its first two frames are the step)")
      ->capture_default_str();
  add_threads(app, threads);
  add_repeats(app, "--rounds", rounds, "alternating rounds of the four calls per step length");
  if (const int rc = parse_command_line(app, argc, argv); rc >= 0) return rc;

  try {
    const FrameSequence seq = read_frames(frame_files(dir));
    tbb::task_arena arena(threads);
    SceneOptions o;
    o.arena = &arena;
    Scene scene({seq.mesh}, o);
    const Positions& a = seq.frames[0];
    scene.step(a, seq.frames[1]);  // builds the front
    std::printf("%s, %zu triangles, %d threads, medians of %d rounds\n", dir.c_str(), seq.mesh.num_faces(), threads,
                rounds);
    std::printf("%-8s %12s %12s %12s %12s %14s\n", "end at", "step s", "free? s", "earliest s", "candidates s",
                "earliest toi");
    for (const double frac : {1.0, 0.25, 0.01}) {
      Positions b(a.mat() + frac * (seq.frames[1].mat() - a.mat()));
      std::vector<double> ts, tf, te, tc;
      double toi = 0;
      StepResult full;
      for (int r = 0; r < rounds; ++r) {
        ts.push_back(seconds([&] { full = scene.step(a, b); }));
        tf.push_back(seconds([&] { (void)scene.is_collision_free(a, b); }));
        te.push_back(seconds([&] { toi = scene.earliest_impact(a, b); }));
        tc.push_back(seconds([&] { (void)scene.candidates(a, b); }));
      }
      if (toi != full.earliest_toi) {
        std::fprintf(stderr, "bench_queries: earliest_impact %.17g differs from the step's %.17g\n", toi,
                     full.earliest_toi);
        return 1;
      }
      std::printf("%-8.2f %12.4f %12.4f %12.4f %12.4f %14.9g\n", frac, median(ts), median(tf), median(te), median(tc),
                  toi);
    }
  } catch (const std::exception& e) {
    return report_failure("bench_queries", e);
  }
  return 0;
}
