// Elementary CCD benchmark: nanoseconds per query of each stage on the benchmark sample
// queries (median of several runs), plus the overall time.
//   bench_ccd [DATA_DIR/sample-queries] [--runs N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <mccd/geometry/ccd.h>
#include <mccd/geometry/ccd_detail.h>
#include <mccd/geometry/query_io.h>

namespace fs = std::filesystem;
using mccd::detail::CcdKind;

namespace {

using clock_type = std::chrono::steady_clock;
volatile int sink = 0;

template <class F>
double median_ns_per_item(int runs, std::size_t items, F&& body) {
  if (items == 0) return 0;
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = clock_type::now();
    body();
    const auto t1 = clock_type::now();
    t.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(items));
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  fs::path dir = fs::path(MCCD_DEFAULT_DATA_DIR) / "sample-queries";
  int runs = 7;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc)
      runs = std::max(1, std::atoi(argv[++i]));
    else
      dir = a;
  }
  if (!fs::exists(dir)) {
    std::fprintf(stderr, "bench_ccd: %s not found\n", dir.string().c_str());
    return 2;
  }
  std::vector<mccd::CcdPoints> q[2];  // 0 VF, 1 EE
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file() || e.path().extension() != ".csv") continue;
    const int k = e.path().string().find("vertex-face") != std::string::npos ? 0 : 1;
    for (const auto& x : mccd::read_query_csv(e.path().string())) q[k].push_back(x.points);
  }
  std::printf("%-11s %8s %10s %10s %10s | %9s %9s %9s %9s\n", "kind", "queries", "after-box", "after-cop", "hits",
              "box ns", "cop ns", "root ns", "all ns");
  for (int k = 0; k < 2; ++k) {
    const CcdKind kind = k == 0 ? CcdKind::VertexFace : CcdKind::EdgeEdge;
    const auto& all = q[k];
    std::vector<mccd::CcdPoints> after_box, after_cop;
    int hits = 0;
    for (const auto& p : all) {
      if (!mccd::detail::ccd_box_overlap(kind, p, 0)) continue;
      after_box.push_back(p);
      if (mccd::detail::ccd_coplanarity_may_hit(kind, p, 0)) after_cop.push_back(p);
      double toi;
      hits += mccd::detail::ccd_run(kind, p, toi, {}, nullptr);
    }
    // Stage times, each per query that reaches the stage.
    const double box = median_ns_per_item(runs, all.size(), [&] {
      int s = 0;
      for (const auto& p : all) s += mccd::detail::ccd_box_overlap(kind, p, 0);
      sink = sink + s;
    });
    const double cop = median_ns_per_item(runs, after_box.size(), [&] {
      int s = 0;
      for (const auto& p : after_box) s += mccd::detail::ccd_coplanarity_may_hit(kind, p, 0);
      sink = sink + s;
    });
    const double full_on_cop = median_ns_per_item(runs, after_cop.size(), [&] {
      int s = 0;
      double toi;
      for (const auto& p : after_cop) s += mccd::detail::ccd_run(kind, p, toi, {}, nullptr);
      sink = sink + s;
    });
    const double overall = median_ns_per_item(runs, all.size(), [&] {
      int s = 0;
      double toi;
      for (const auto& p : all) s += mccd::detail::ccd_run(kind, p, toi, {}, nullptr);
      sink = sink + s;
    });
    // Root stage: the whole test on the queries that reach it, less the two filters.
    const double root = std::max(0.0, full_on_cop - box - cop);
    std::printf("%-11s %8zu %10zu %10zu %10d | %9.1f %9.1f %9.1f %9.1f\n", k == 0 ? "vertex-face" : "edge-edge",
                all.size(), after_box.size(), after_cop.size(), hits, box, cop, root, overall);
  }
  std::printf("ns per query reaching the stage (box: all queries; cop: after the box test; root: after the\n"
              "coplanarity filter, net of the filters); all: the whole test, per query. Median of %d runs.\n",
              runs);
  return 0;
}
