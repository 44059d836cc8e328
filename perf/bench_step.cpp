// One real step, timed per stage: the engine's own view of a Time-of-Impact scene (no truth
// check), for measuring changes to the core. Repeats the step from scratch (a new Scene each
// time, so the front is built from the root as in `mccd toi-check`) and prints the medians.
//   bench_step [DIR] [--bvh median|sah] [--leaf 1..16] [--method fbd|phc|traverse] [--threads N] [--repeat K]
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <mccd/core/scene.h>
#include <mccd/geometry/error.h>
#include <mccd/geometry/frame_sequence.h>

using namespace mccd;

int main(int argc, char** argv) {
  std::string dir = std::string(MCCD_DEFAULT_DATA_DIR) + "/toi/cloth-ball";
  SceneOptions opt;
  int threads = 1, repeat = 3;
  try {
    for (int i = 1; i < argc; ++i) {
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw Error(std::string(argv[i]) + " needs a value");
        return argv[++i];
      };
      if (!std::strcmp(argv[i], "--bvh")) opt.bvh = parse_bvh_build(value().c_str());
      else if (!std::strcmp(argv[i], "--leaf")) opt.leaf_size = unsigned(std::atoi(value().c_str()));
      else if (!std::strcmp(argv[i], "--method")) opt.method = parse_method(value().c_str());
      else if (!std::strcmp(argv[i], "--threads")) threads = std::max(1, std::atoi(value().c_str()));
      else if (!std::strcmp(argv[i], "--repeat")) repeat = std::max(1, std::atoi(value().c_str()));
      else if (argv[i][0] != '-') dir = argv[i];
      else throw Error(std::string("unknown option ") + argv[i]);
    }
    std::vector<std::string> files;
    for (const auto& e : std::filesystem::directory_iterator(dir + "/frames"))
      if (e.path().extension() == ".ply") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    const FrameSequence seq = read_frames(files);
    tbb::task_arena arena(threads);
    opt.arena = &arena;
    std::vector<double> total, build, update, refit, search, orphans, join;
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
      orphans.push_back(r.stats.t_orphans);
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
    std::printf("  median s: scene build %.3f, step %.3f (update %.3f, refit %.3f, search %.3f, orphans %.3f, join %.3f)\n",
                med(build), med(total), med(update), med(refit), med(search), med(orphans), med(join));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_step: %s\n", e.what());
    return 2;
  }
  return 0;
}
