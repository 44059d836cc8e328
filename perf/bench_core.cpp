// Whole-step benchmark: methods and thread counts on generated scenes or frame files.
// Each variant is first checked against `traverse` on the same steps (identical contacts),
// then timed; the first step (front build) is reported apart, the rest as a median.
//   bench_core [--scene cloth|spheres|random|tube] [--size K] [--frames N]
//              [--threads 1,2,4] [--methods traverse,front] [--csv FILE]
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <mccd/core/scene.h>
#include "fixtures/scenes.h"
#include <mccd/geometry/error.h>

using namespace mccd;

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(item);
  return out;
}

struct Row {
  std::string scene, method;
  int threads;
  double first_ms, median_ms;
  std::uint64_t volume_tests, elementary_tests, contacts;
};

}  // namespace

int main(int argc, char** argv) {
  std::string scene_name = "cloth", csv, methods_arg = "traverse,front",
              threads_arg = std::to_string(tbb::info::default_concurrency());
  int size = 8, frames = 21;
  for (int i = 1; i < argc; ++i) {
    auto next = [&](const char* opt) -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_core: %s needs a value\n", opt);
        std::exit(2);
      }
      return argv[++i];
    };
    if (!std::strcmp(argv[i], "--scene")) scene_name = next("--scene");
    else if (!std::strcmp(argv[i], "--size")) size = std::atoi(next("--size").c_str());
    else if (!std::strcmp(argv[i], "--frames")) frames = std::atoi(next("--frames").c_str());
    else if (!std::strcmp(argv[i], "--threads")) threads_arg = next("--threads");
    else if (!std::strcmp(argv[i], "--methods")) methods_arg = next("--methods");
    else if (!std::strcmp(argv[i], "--csv")) csv = next("--csv");
    else {
      std::fprintf(stderr, "bench_core: unknown argument %s\n", argv[i]);
      return 2;
    }
  }
  try {
    const AnimatedScene s = make_scene(scene_name, size, frames);
    std::printf("scene %s: %zu triangles, %zu steps\n", s.name.c_str(), s.num_triangles(), s.frames.size() - 1);
    auto views = [](const std::vector<Positions>& f) { return std::vector<PositionsView>(f.begin(), f.end()); };

    // reference contacts, one vector per step
    std::vector<std::vector<Contact>> reference;
    {
      Scene ref(s.meshes);
      for (std::size_t f = 1; f < s.frames.size(); ++f)
        reference.push_back(ref.advance(views(s.frames[f]), Method::Traverse).contacts);
    }

    std::vector<Row> rows;
    for (const std::string& m : split(methods_arg)) {
      const Method method = parse_method(m.c_str());
      for (const std::string& t : split(threads_arg)) {
        const int threads = std::atoi(t.c_str());
        if (threads < 1) throw Error("--threads: bad count '" + t + "'");
        tbb::task_arena arena(threads);
        SceneOptions opt;
        opt.arena = &arena;
        Scene scene(s.meshes, opt);
        std::vector<double> ms;
        Row row{s.name, m, threads, 0, 0, 0, 0, 0};
        for (std::size_t f = 1; f < s.frames.size(); ++f) {
          StepResult r = scene.advance(views(s.frames[f]), method);
          if (r.contacts != reference[f - 1]) {
            std::fprintf(stderr, "bench_core: %s with %d threads differs from traverse at step %zu\n", m.c_str(),
                         threads, f);
            return 1;
          }
          if (f == 1)
            row.first_ms = 1e3 * r.stats.t_total;  // the front build: reported apart
          else
            ms.push_back(1e3 * r.stats.t_total);
          row.volume_tests += r.stats.volume_tests;
          row.elementary_tests += r.stats.vf_tests + r.stats.ee_tests;
          row.contacts += r.contacts.size();
        }
        std::sort(ms.begin(), ms.end());
        row.median_ms = ms.empty() ? row.first_ms : ms[ms.size() / 2];
        rows.push_back(row);
      }
    }
    std::printf("%-8s %-10s %7s %10s %11s %13s %13s %10s\n", "scene", "method", "threads", "first_ms", "median_ms",
                "volume_tests", "elem_tests", "contacts");
    for (const Row& r : rows)
      std::printf("%-8s %-10s %7d %10.2f %11.2f %13llu %13llu %10llu\n", r.scene.c_str(), r.method.c_str(), r.threads,
                  r.first_ms, r.median_ms, (unsigned long long)r.volume_tests, (unsigned long long)r.elementary_tests,
                  (unsigned long long)r.contacts);
    if (!csv.empty()) {
      const std::string tmp = csv + ".tmp";
      {
        std::ofstream out(tmp);
        out << "scene,method,threads,first_ms,median_ms,volume_tests,elementary_tests,contacts\n";
        for (const Row& r : rows)
          out << r.scene << ',' << r.method << ',' << r.threads << ',' << r.first_ms << ',' << r.median_ms << ','
              << r.volume_tests << ',' << r.elementary_tests << ',' << r.contacts << '\n';
        if (!out) throw Error(csv + ": write failed");
      }
      std::rename(tmp.c_str(), csv.c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_core: %s\n", e.what());
    return 2;
  }
  return 0;
}
