// What the flow graph of a step costs: the same steps run through the graph and with the
// stages called in sequence (SceneOptions::flow_graph), alternating, on a small generated
// scene (about 1K triangles: below SceneOptions::flow_graph's threshold, both run the stages in
// sequence, so this row shows that the option costs nothing there) and on the real cloth-ball step.
//   bench_graph [--threads N] [--rounds K]
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/frame_sequence.h>

#include "fixtures/scenes.h"
#include "harness/cli.h"

using namespace mccd;
using namespace mccd::bench;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

/// Median seconds per step of `frames` (advance after advance), graph on and off, alternating
/// rounds; each round is a fresh scene with its first step (the front build) left out.
void compare(const char* name, const std::vector<TriMesh>& meshes, const std::vector<std::vector<Positions>>& frames,
             tbb::task_arena& arena, int rounds) {
  std::vector<double> with, without;
  for (int r = 0; r < rounds; ++r)
    for (bool graph : {true, false}) {
      SceneOptions o;
      o.arena = &arena;
      o.flow_graph = graph;
      Scene sc(meshes, o);
      for (std::size_t f = 1; f < frames.size(); ++f) {
        const std::vector<PositionsView> next(frames[f].begin(), frames[f].end());
        const auto t0 = std::chrono::steady_clock::now();
        sc.advance(next);
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (f > 1) (graph ? with : without).push_back(s);
      }
    }
  const double a = median(with), b = median(without);
  std::printf("%-12s graph %10.1f us/step, in sequence %10.1f us/step, graph costs %+8.1f us (%+.1f%%)\n", name, 1e6 * a,
              1e6 * b, 1e6 * (a - b), 100 * (a - b) / b);
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 2, rounds = 5;
  CLI::App app{"Times steps run through the step's flow graph against the same stages called in sequence,\n"
               "alternating, on a small generated cloth and on the real cloth-ball step (when its data is there).",
               "bench_graph"};
  add_threads(app, threads);
  add_repeats(app, "--rounds", rounds, "alternating rounds (graph on, then off)");
  if (const int rc = parse_command_line(app, argc, argv); rc >= 0) return rc;

  try {
    tbb::task_arena arena(threads);
    std::printf("%d threads, %d alternating rounds\n", threads, rounds);
    const AnimatedScene small = make_folding_cloth(22, 201);  // 968 triangles, 200 steps
    compare("cloth 968", small.meshes, small.frames, arena, rounds);
    const std::string dir = std::string(MCCD_DEFAULT_DATA_DIR) + "/toi/cloth-ball/frames";
    if (std::filesystem::is_directory(dir)) {
      std::vector<std::string> files;
      for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().extension() == ".ply") files.push_back(e.path().string());
      std::sort(files.begin(), files.end());
      const FrameSequence seq = read_frames(files);
      // 92 -> 93 -> 92 -> 93: the front is tracked after the first step
      std::vector<std::vector<Positions>> frames;
      for (int k = 0; k < 6; ++k) frames.push_back({seq.frames[k % 2]});
      compare("cloth-ball", {seq.mesh}, frames, arena, rounds);
    } else {
      std::printf("cloth-ball: %s not found, skipped\n", dir.c_str());
    }
  } catch (const std::exception& e) {
    return report_failure("bench_graph", e);
  }
  return 0;
}
