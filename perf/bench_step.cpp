// One real step, timed per stage: the engine's own view of a Time-of-Impact scene (no truth
// check), for measuring changes to the core. Repeats the step from scratch (a new Scene each
// time, so the front is built from the root as in `mccd toi-check`) and prints the medians.
//   bench_step [DIR] [--bvh median|sah] [--leaf 1..21] [--method fbd|phc|traverse] [--threads N] [--repeat K]
// DIR: a Time-of-Impact scene, DIR/frames/*.ply (default: the shared data's toi/cloth-ball).
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/error.h>
#include <mccd/geometry/frame_sequence.h>

#include "harness/cli.h"

using namespace mccd;
using namespace mccd::bench;

int main(int argc, char** argv) {
  std::string dir = std::string(MCCD_DEFAULT_DATA_DIR) + "/toi/cloth-ball";
  SceneOptions opt;
  int threads = 1, repeat = 3;
  CLI::App app{"Times one real step per stage (scene build, update, refit, search, self stage, join), repeated from\n"
               "scratch with a new scene each time; prints the step's counts and the median seconds.",
               "bench_step"};
  app.add_option("DIR", dir, "Time-of-Impact scene folder with frames/*.ply (its first two frames are the step)")
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--bvh", [&opt](const std::string& v) { opt.bvh = parse_bvh_build(v.c_str()); },
         "how the scene BVH is built: median or sah (default: sah)")
      ->type_name("NAME")
      ->check(parsed_by(parse_bvh_build));
  app.add_option("--leaf", opt.leaf_size, "triangles per BVH leaf, 1 to 21 (default: 21 with sah, 1 with median)")
      ->type_name("K")
      ->check(integer_in(1, 21));
  app.add_option_function<std::string>(
         "--method", [&opt](const std::string& v) { opt.method = parse_method(v.c_str()); },
         "how candidate pairs are found: fbd, phc, traverse or bruteforce (default: fbd)")
      ->type_name("NAME")
      ->check(parsed_by(parse_method));
  add_threads(app, threads);
  add_repeats(app, "--repeat", repeat, "timed steps, each on a new scene");
  if (const int rc = parse_command_line(app, argc, argv); rc >= 0) return rc;

  try {
    const FrameSequence seq = read_frames(frame_files(dir));
    tbb::task_arena arena(threads);
    opt.arena = &arena;
    std::vector<double> total, build, update, refit, search, self, join;
    StepResult r;
    for (int k = 0; k < repeat; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      Scene scene({seq.mesh}, opt);
      build.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      r = scene.step(seq.frames[0], seq.frames[1]);
      total.push_back(r.stats.t_total);
      update.push_back(r.stats.t_update);
      refit.push_back(r.stats.t_refit);
      search.push_back(r.stats.t_front);
      self.push_back(r.stats.t_self);
      join.push_back(r.stats.t_contacts);
    }
    auto med = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v[v.size() / 2];
    };
    const StepStats& s = r.stats;
    std::printf("%s: bvh %s, method %s, %d threads, %d runs\n", dir.c_str(), to_string(opt.bvh), to_string(opt.method),
                threads, repeat);
    std::printf("  contacts %zu (VF %llu, EE %llu), volume tests %llu, triangle tests %llu, leaf pairs %llu, elementary VF %llu EE %llu "
                "(past filters %llu / %llu), front %llu nodes (%.1f MB)\n",
                r.contacts.size(), (unsigned long long)s.vf_contacts, (unsigned long long)s.ee_contacts,
                (unsigned long long)s.volume_tests, (unsigned long long)s.triangle_tests, (unsigned long long)s.leaf_pairs, (unsigned long long)s.vf_tests,
                (unsigned long long)s.ee_tests, (unsigned long long)s.vf_ccd.root_tests,
                (unsigned long long)s.ee_ccd.root_tests, (unsigned long long)s.front_size, s.front_bytes / 1e6);
    std::printf("  median s: scene build %.3f, step %.3f (update %.3f, refit %.3f, search %.3f, self %.3f, join %.3f)\n",
                med(build), med(total), med(update), med(refit), med(search), med(self), med(join));
  } catch (const std::exception& e) {
    return report_failure("bench_step", e);
  }
  return 0;
}
