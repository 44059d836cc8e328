// bench_core: the paper's evaluation in one command. For each scene (the four generated ones
// and the real cloth-ball step, as one step and as 5 sub-steps) x method x thread count: a
// warm-up whose contacts are checked step by step against the serial result (traverse, one
// thread), then repeated timed runs, and one 1-thread run per method measuring each stage's
// work and span, from which every thread count is predicted. Writes perf/results/<machine>/: runs.csv (every run),
// results.md (tables, serial fractions, the paper's figures) and PNG plots (gnuplot).
//   bench_core [--scenes a,b] [--size tiny|small|full] [--steps N] [--methods traverse,phc,fbd]
//              [--threads 1,2] [--repeats R] [--out DIR] [--machine NAME] [--no-plots]
#include <oneapi/tbb/info.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <mccd/geometry/error.h>

#include "generators/scene_cache.h"
#include "harness/cli.h"
#include "harness/plots.h"
#include "harness/report.h"
#include "harness/summary.h"
#include "harness/sweep.h"
#include "harness/workload.h"

using namespace mccd;
using namespace mccd::bench;

namespace {

std::string now_text() {
  char b[64];
  const std::time_t t = std::time(nullptr);
  std::strftime(b, sizeof b, "%Y-%m-%d %H:%M UTC", std::gmtime(&t));
  return b;
}

std::string joined(int argc, char** argv) {
  std::string s = "bench_core";
  for (int i = 1; i < argc; ++i) s += std::string(" ") + argv[i];
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Times whole CCD steps per scene, method and thread count after checking every variant's contacts\n"
               "against the serial result; writes a CSV of every run, a Markdown report and PNG plots.",
               "bench_core"};
  std::vector<std::string> scenes = workload_names(), methods{"traverse", "phc", "fbd"};
  std::vector<int> threads;
  for (int t = 1; t <= tbb::info::default_concurrency(); ++t) threads.push_back(t);
  GeneratedSource source;
  int repeats = 3;
  std::string out, machine, data_dir = MCCD_DEFAULT_DATA_DIR;
  bool no_plots = false, no_work_span = false;
  if (const char* d = std::getenv("MCCD_DATA_DIR"); d && *d) data_dir = d;
  app.add_option("--scenes", scenes, "scenes: cloth-ball, n-body, bart, skirt, cloth-ball-toi, cloth-ball-toi-5sub")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--size", source.size, "size of the generated scenes: tiny, small or full")->capture_default_str();
  app.add_option("--seed", source.seed, "seed of the generated scenes")->capture_default_str();
  app.add_option("--steps", source.steps, "frame intervals timed per generated scene (its last ones)")
      ->check(mccd::bench::integer_in(1, 1000))
      ->capture_default_str();
  app.add_option("--methods", methods, "methods: traverse, phc, fbd (bruteforce for small scenes)")
      ->delimiter(',')
      ->capture_default_str();
  app.add_option("--threads", threads, "thread counts (default: 1 up to the hardware threads)")
      ->delimiter(',')
      ->check(mccd::bench::integer_in(1, mccd::bench::kMaxThreads));
  app.add_option("--repeats", repeats, "timed runs per variant, after the warm-up")->check(mccd::bench::integer_in(1, mccd::bench::kMaxRepeats))->capture_default_str();
  app.add_option("--cache", source.cache_dir, "scene cache (default: $MCCD_SCENE_CACHE, $XDG_CACHE_HOME/mccd/scenes, ~/.cache/mccd/scenes)");
  app.add_option("--data", data_dir, "shared data folder with toi/cloth-ball (default: ../shared/data or $MCCD_DATA_DIR)")
      ->capture_default_str();
  app.add_option("--machine", machine, "name of the results folder (default: from the CPU model and thread count)");
  app.add_option("--out", out, "results folder (default: perf/results/<machine> in the source tree)");
  app.add_flag("--no-plots", no_plots, "skip the PNG plots");
  app.add_flag("--no-work-span", no_work_span,
               "skip the 1-thread run per method that measures each stage's work and span (and predicts each "
               "thread count)");
  if (const int rc = mccd::bench::parse_command_line(app, argc, argv); rc >= 0) return rc;

  try {
    SweepOptions opt;
    opt.methods.clear();
    for (const std::string& m : methods) opt.methods.push_back(parse_method(m.c_str()));
    opt.threads = threads;
    opt.repeats = repeats;
    opt.work_span_runs = !no_work_span;
    opt.progress = [](const std::string& line) {
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    };
    if (source.cache_dir.empty()) source.cache_dir = gen::default_cache_dir();
    if (machine.empty()) machine = default_machine_name();
    if (out.empty()) out = (std::filesystem::path(MCCD_SOURCE_DIR) / "perf" / "results" / machine).string();
    if (!no_plots && !gnuplot_available())
      throw Error("gnuplot with the pngcairo terminal is needed for the plots (bash cmake/install-deps.sh), or pass --no-plots");

    MachineInfo info;
    info.name = machine, info.cpu = cpu_model(), info.hardware_threads = tbb::info::default_concurrency();
    info.load_before = load_average(), info.date = now_text(), info.command = joined(argc, argv), info.repeats = repeats;
    info.cores_before = time_cores_alone();
    const auto start = std::chrono::steady_clock::now();
    std::vector<RunRecord> runs;
    std::vector<Workload> loaded;
    for (const std::string& name : scenes) {
      Workload w = load_workload(name, source, data_dir);
      std::printf("== %s: %zu triangles, %zu steps over %d frame intervals\n", w.name.c_str(), w.mesh.num_faces(),
                  w.steps(), w.intervals);
      std::vector<RunRecord> r = sweep_workload(w, opt);
      runs.insert(runs.end(), r.begin(), r.end());
      loaded.push_back(std::move(w));
    }
    info.load_after = load_average();
    info.cores_after = time_cores_alone();

    const std::vector<VariantSummary> variants = summarize(runs);
    std::vector<SceneSummary> summaries;
    for (const Workload& w : loaded) summaries.push_back(summarize_scene(w, variants));
    std::filesystem::create_directories(out);
    write_runs_csv((std::filesystem::path(out) / "runs.csv").string(), runs);
    write_report((std::filesystem::path(out) / "results.md").string(), info, summaries, variants);
    std::printf("\n%s\n", report_markdown(info, summaries, variants).c_str());
    if (!no_plots)
      for (const std::string& f : draw_plots(out, machine, summaries, variants)) std::printf("plot: %s/%s\n", out.c_str(), f.c_str());
    std::printf("results in %s (%.0f s)\n", out.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_core: %s\n", e.what());
    return mccd::bench::kExitUsage;
  }
  return 0;
}
