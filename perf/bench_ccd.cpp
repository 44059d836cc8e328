// Elementary CCD benchmark: nanoseconds per call of each stage, and of the whole test, on the
// benchmark sample queries and, optionally, on the feature pairs of one real step.
//   bench_ccd [DATA_DIR/sample-queries] [--runs N] [--step TOI_DIR] [--min-distance D]
//             [--only SET_PREFIX] [--limit N]
// --step loads a Time-of-Impact step (TOI_DIR/frames/*.ply, two frames; boxes/*{vf,ee}.json)
// and times two sets of pairs per kind: the pairs listed in boxes/ (nearly all true contacts)
// and every non-adjacent pair whose swept axis-aligned boxes overlap (what a broad phase hands
// the elementary tests: mostly pairs that do not collide; an evenly spaced subset).
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <mccd/geometry/ccd.h>
#include <mccd/geometry/ccd_detail.h>
#include <mccd/geometry/error.h>
#include <mccd/geometry/frame_sequence.h>
#include <mccd/geometry/lane_masks.h>
#include <mccd/geometry/query_io.h>
#include <mccd/geometry/topology.h>

#include "harness/cli.h"

namespace fs = std::filesystem;
using mccd::CcdPoints;
using mccd::detail::CcdKind;
using mccd::bench::integer_in;
using mccd::bench::kMaxRepeats;

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

struct QuerySet {
  std::string name;
  CcdKind kind;
  std::vector<CcdPoints> q;
};

// ---- one real step --------------------------------------------------------------------------

struct Step {
  mccd::FrameSequence seq;
  mccd::MeshTopology topo;
};

// Swept axis-aligned box of a list of vertices over the step.
struct Box {
  double lo[3], hi[3];
  std::uint32_t id;
};

Box swept_box(const Step& s, const std::uint32_t* v, int n, std::uint32_t id) {
  Box b{{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, id};
  for (int i = 0; i < n; ++i)
    for (const auto* f : {&s.seq.frames[0], &s.seq.frames[1]}) {
      const mccd::Vec3 x = f->point(v[i]);
      for (int k = 0; k < 3; ++k) b.lo[k] = std::min(b.lo[k], x[k]), b.hi[k] = std::max(b.hi[k], x[k]);
    }
  return b;
}

// Every pair (x from `a`, y from `b`; a == b: each unordered pair once) whose boxes overlap,
// by sorting on x and sweeping.
template <class Emit>
void sweep_pairs(std::vector<Box> a, std::vector<Box> b, bool same, Emit&& emit) {
  auto by_lo = [](const Box& x, const Box& y) { return x.lo[0] < y.lo[0]; };
  std::sort(a.begin(), a.end(), by_lo);
  if (!same) std::sort(b.begin(), b.end(), by_lo);
  const std::vector<Box>& B = same ? a : b;
  auto overlap_yz = [](const Box& x, const Box& y) {
    return x.lo[1] <= y.hi[1] && y.lo[1] <= x.hi[1] && x.lo[2] <= y.hi[2] && y.lo[2] <= x.hi[2];
  };
  std::size_t j0 = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Box& x = a[i];
    if (same) {
      for (std::size_t j = i + 1; j < a.size() && a[j].lo[0] <= x.hi[0]; ++j)
        if (overlap_yz(x, a[j])) emit(x.id, a[j].id);
      continue;
    }
    // Boxes of b starting before x ends; those ending before x starts are skipped.
    while (j0 < B.size() && B[j0].hi[0] < x.lo[0] && B[j0].lo[0] <= x.lo[0]) ++j0;
    for (std::size_t j = j0; j < B.size() && B[j].lo[0] <= x.hi[0]; ++j)
      if (B[j].hi[0] >= x.lo[0] && overlap_yz(x, B[j])) emit(x.id, B[j].id);
  }
}

CcdPoints points(const Step& s, std::array<std::uint32_t, 4> ids) {
  CcdPoints p;
  for (int k = 0; k < 4; ++k) p.start[k] = s.seq.frames[0].point(ids[k]), p.end[k] = s.seq.frames[1].point(ids[k]);
  return p;
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw std::runtime_error(p.string() + ": cannot open");
  return nlohmann::json::parse(in);
}

fs::path find_suffix(const fs::path& dir, const std::string& suffix) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().ends_with(suffix)) return e.path();
  throw std::runtime_error(dir.string() + ": no *" + suffix);
}

void load_step(const fs::path& dir, std::vector<QuerySet>& sets) {
  Step s{mccd::read_frames(mccd::bench::frame_files(dir)), {}};
  s.topo = mccd::MeshTopology(s.seq.mesh.num_vertices(), s.seq.mesh.faces);
  const std::uint64_t nv = s.topo.num_vertices(), ne = s.topo.num_edges();
  const auto& faces = s.topo.faces();
  const auto& edges = s.topo.edges();
  // Listed pairs (global ids: vertices, then edges, then faces).
  QuerySet lvf{"listed VF", CcdKind::VertexFace, {}}, lee{"listed EE", CcdKind::EdgeEdge, {}};
  for (const auto& pr : read_json(find_suffix(dir / "boxes", "vf.json"))) {
    std::uint64_t v = pr[0].get<std::uint64_t>(), f = pr[1].get<std::uint64_t>();
    if (v >= nv) std::swap(v, f);
    const auto& t = faces[f - nv - ne];
    lvf.q.push_back(points(s, {std::uint32_t(v), t[0], t[1], t[2]}));
  }
  for (const auto& pr : read_json(find_suffix(dir / "boxes", "ee.json"))) {
    const auto& a = edges[pr[0].get<std::uint64_t>() - nv];
    const auto& b = edges[pr[1].get<std::uint64_t>() - nv];
    lee.q.push_back(points(s, {a[0], a[1], b[0], b[1]}));
  }
  // Swept-box pairs.
  std::vector<Box> vb, fb, eb;
  for (std::uint32_t v = 0; v < nv; ++v) vb.push_back(swept_box(s, &v, 1, v));
  for (std::uint32_t f = 0; f < faces.size(); ++f) fb.push_back(swept_box(s, faces[f].data(), 3, f));
  for (std::uint32_t e = 0; e < ne; ++e) eb.push_back(swept_box(s, edges[e].data(), 2, e));
  QuerySet bvf{"box VF", CcdKind::VertexFace, {}}, bee{"box EE", CcdKind::EdgeEdge, {}};
  sweep_pairs(vb, fb, false, [&](std::uint32_t v, std::uint32_t f) {
    const auto& t = faces[f];
    if (t[0] != v && t[1] != v && t[2] != v) bvf.q.push_back(points(s, {v, t[0], t[1], t[2]}));
  });
  sweep_pairs(eb, eb, true, [&](std::uint32_t x, std::uint32_t y) {
    const auto& a = edges[x];
    const auto& b = edges[y];
    if (a[0] != b[0] && a[0] != b[1] && a[1] != b[0] && a[1] != b[1]) bee.q.push_back(points(s, {a[0], a[1], b[0], b[1]}));
  });
  // The box sets are several times larger than what the engine's tighter volumes let through:
  // keep an evenly spaced subset of at most 300,000 pairs each.
  for (QuerySet* q : {&bvf, &bee}) {
    const std::size_t stride = (q->q.size() + 299999) / 300000;
    std::vector<CcdPoints> kept;
    for (std::size_t i = 0; i < q->q.size(); i += std::max<std::size_t>(stride, 1)) kept.push_back(q->q[i]);
    q->name += " /" + std::to_string(stride);
    q->q = std::move(kept);
  }
  for (QuerySet* q : {&lvf, &lee, &bvf, &bee}) sets.push_back(std::move(*q));
}

using mccd::detail::CcdPath;

bool run(CcdKind kind, const CcdPoints& p, double& toi, const mccd::CcdOptions& o, mccd::CcdCounters* c,
         CcdPath path) {
  return mccd::detail::ccd_run(kind, p, toi, o, c, path);
}

/// The queries as the engine hands them to the lane kernels: positions by vertex id, four fresh
/// vertices per query.
struct LaneLayout {
  std::vector<double> x0, x1;
  std::vector<std::uint32_t> ids;
  explicit LaneLayout(const std::vector<CcdPoints>& queries) {
    for (const CcdPoints& p : queries)
      for (int k = 0; k < 4; ++k) {
        ids.push_back(static_cast<std::uint32_t>(x0.size() / 3));
        for (int c = 0; c < 3; ++c) x0.push_back(p.start[k][c]), x1.push_back(p.end[k][c]);
      }
  }
  const std::uint32_t (*query_ids() const)[4] { return reinterpret_cast<const std::uint32_t(*)[4]>(ids.data()); }
};

/// The engine's way (no minimum distance): the fast path in lanes for windows of 512 queries
/// (LaneKernels::fast_tests), the whole scalar test for the queries it leaves open. Returns the
/// contacts found; `toi_sum` (when given) their times' sum.
int run_lanes(CcdKind kind, const std::vector<CcdPoints>& queries, const LaneLayout& lay, const mccd::CcdOptions& o,
              double* toi_sum = nullptr, std::size_t* open = nullptr) {
  constexpr std::size_t kWindow = 512;
  std::uint8_t decided[kWindow];
  double toi[kWindow];
  int hits = 0;
  const mccd::detail::LaneKernels& k = mccd::detail::lane_kernels();
  for (std::size_t first = 0; first < queries.size(); first += kWindow) {
    const std::size_t m = std::min(kWindow, queries.size() - first);
    k.fast_tests(kind == CcdKind::VertexFace, lay.x0.data(), lay.x1.data(), lay.query_ids() + first, m, decided, toi);
    for (std::size_t i = 0; i < m; ++i) {
      if (open) *open += decided[i] == mccd::detail::kFastOpen;
      double t = toi[i];
      const bool hit = decided[i] == mccd::detail::kFastOpen ? run(kind, queries[first + i], t, o, nullptr, CcdPath::Fast)
                                                            : decided[i] == mccd::detail::kFastHit;
      hits += hit;
      if (hit && toi_sum) *toi_sum += t;
    }
  }
  return hits;
}

// Medians of the paths' ns per query over `queries`, the runs alternating between them: search
// only, fast path first, and (no minimum distance) the fast path in lanes first.
std::array<double, 3> median_paths(int runs, const std::vector<CcdPoints>& queries, CcdKind kind,
                                   const mccd::CcdOptions& opt) {
  const bool lanes = !(opt.min_distance > 0);
  const LaneLayout lay(lanes ? queries : std::vector<CcdPoints>{});
  std::vector<double> t[3];
  for (int r = 0; r < runs; ++r)
    for (int k = 0; k < (lanes ? 3 : 2); ++k) {
      const CcdPath path = k == 0 ? CcdPath::SearchOnly : CcdPath::Fast;
      t[k].push_back(median_ns_per_item(1, queries.size(), [&] {
        int s = 0;
        double toi;
        if (k == 2)
          s = run_lanes(kind, queries, lay, opt);
        else
          for (const auto& p : queries) s += run(kind, p, toi, opt, nullptr, path);
        sink = sink + s;
      }));
    }
  std::array<double, 3> m{};
  for (int k = 0; k < 3; ++k) {
    std::sort(t[k].begin(), t[k].end());
    m[k] = t[k].empty() ? 0 : t[k][t[k].size() / 2];
  }
  return m;
}

void bench(const QuerySet& set, int runs, const mccd::CcdOptions& opt) {
  const CcdKind kind = set.kind;
  const auto& all = set.q;
  std::vector<CcdPoints> after_box, after_cop;
  for (const auto& p : all) {
    if (!mccd::detail::ccd_box_overlap(kind, p, opt.min_distance)) continue;
    after_box.push_back(p);
    if (mccd::detail::ccd_coplanarity_may_hit(kind, p, opt.min_distance)) after_cop.push_back(p);
  }
  mccd::CcdCounters c[2];
  double toi_sum[2] = {0, 0};
  for (int k = 0; k < 2; ++k)
    for (const auto& p : all) {
      double toi = 0;
      if (run(kind, p, toi, opt, &c[k], k == 0 ? CcdPath::SearchOnly : CcdPath::Fast)) toi_sum[k] += toi;
    }
  // Stage times, each per query that reaches the stage.
  const double box = median_ns_per_item(runs, all.size(), [&] {
    int s = 0;
    for (const auto& p : all) s += mccd::detail::ccd_box_overlap(kind, p, opt.min_distance);
    sink = sink + s;
  });
  const double cop = median_ns_per_item(runs, after_box.size(), [&] {
    int s = 0;
    for (const auto& p : after_box) s += mccd::detail::ccd_coplanarity_may_hit(kind, p, opt.min_distance);
    sink = sink + s;
  });
  const auto past = median_paths(runs, after_cop, kind, opt);
  const auto overall = median_paths(runs, all, kind, opt);
  // the lanes' way finds the same contacts at the same times as the fast path (checked here)
  bool lanes_same = true;
  std::size_t lane_open = 0;
  if (!(opt.min_distance > 0)) {
    double lane_toi = 0;
    run_lanes(kind, after_cop, LaneLayout(after_cop), opt, nullptr, &lane_open);
    const int lane_hits = run_lanes(kind, all, LaneLayout(all), opt, &lane_toi);
    lanes_same = lane_hits == static_cast<int>(c[1].hits) && lane_toi == toi_sum[1];
  }
  const mccd::CcdCounters& f = c[1];
  const double n = static_cast<double>(std::max<std::uint64_t>(f.root_tests, 1));
  std::printf("%-11s %8zu %9zu %9zu %7llu%s | %6.1f %6.1f | %7.1f %6.1f %6.1f | %7.1f %6.1f %6.1f | %5.1f%% %5.1f%% %5.1f%% %5.1f %5.1f | %.9g %.9g\n",
              set.name.c_str(), all.size(), after_box.size(), after_cop.size(), (unsigned long long)f.hits,
              c[0].hits == f.hits && lanes_same ? " " : "!", box, cop, past[0], past[1], past[2], overall[0],
              overall[1], overall[2], 100.0 * double(f.fast_hits) / n, 100.0 * double(f.fast_misses) / n,
              100.0 * double(lane_open) / static_cast<double>(std::max<std::size_t>(after_cop.size(), 1)), double(c[0].pieces) / n, double(f.pieces) / n, toi_sum[0], toi_sum[1]);
}

}  // namespace

int main(int argc, char** argv) {
  fs::path dir = fs::path(MCCD_DEFAULT_DATA_DIR) / "sample-queries";
  fs::path step;
  int runs = 7;
  std::string only;       // run only the sets whose name starts with this
  std::size_t limit = 0;  // at most this many queries per set (0: all)
  mccd::CcdOptions opt;
  CLI::App app{"Times the elementary CCD tests per stage (ns per call) on the benchmark sample queries and,\n"
               "with --step, on the feature pairs of one real step; the search-only, fast and lane paths alternate.",
               "bench_ccd"};
  app.add_option("DIR", dir, "sample queries folder: every *.csv below it (vertex-face in the path: VF, else EE)")
      ->capture_default_str();
  mccd::bench::add_repeats(app, "--runs", runs, "timed runs per stage and path (medians)");
  app.add_option("--step", step,
                 "also a Time-of-Impact step: TOI_DIR/frames/*.ply (two frames), TOI_DIR/boxes/*vf.json and *ee.json")
      ->type_name("TOI_DIR");
  app.add_option("--min-distance", opt.min_distance,
                 "report pairs that come within this distance (a finite number >= 0)")
      ->type_name("D")
      ->check(mccd::bench::non_negative_number())
      ->capture_default_str();
  app.add_option("--only", only, "run only the sets whose name starts with this (e.g. sample, listed, box)")
      ->type_name("SET_PREFIX");
  app.add_option("--limit", limit, "at most this many queries per set, 0 to 1000000000 (0: all)")
      ->type_name("N")
      ->check(integer_in(0, 1'000'000'000))
      ->capture_default_str();
  if (const int rc = mccd::bench::parse_command_line(app, argc, argv); rc >= 0) return rc;

  try {
    std::vector<QuerySet> sets{{"sample VF", CcdKind::VertexFace, {}}, {"sample EE", CcdKind::EdgeEdge, {}}};
    if (!fs::exists(dir)) throw mccd::Error(dir.string() + " not found");
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      if (!e.is_regular_file() || e.path().extension() != ".csv") continue;
      const int k = e.path().string().find("vertex-face") != std::string::npos ? 0 : 1;
      for (const auto& x : mccd::read_query_csv(e.path().string())) sets[k].q.push_back(x.points);
    }
    if (!step.empty()) load_step(step, sets);
    std::printf("%-11s %8s %9s %9s %8s | %6s %6s | %21s | %21s | %6s %6s %6s %11s | %s\n", "set", "queries", "after-box",
                "after-cop", "hits", "box", "cop", "past: S / F / L", "all: S / F / L", "f-hit", "f-miss",
                "l-open", "pieces S/F", "toi sum S / F");
    for (QuerySet& s : sets) {
      if (!s.name.starts_with(only)) continue;
      if (limit > 0 && s.q.size() > limit) s.q.resize(limit);
      bench(s, runs, opt);
    }
    std::printf(
        "ns per query: box (all queries), cop (after the box test), past (the whole test on the queries past\n"
        "both filters), all (the whole test, every query); S: search only, F: fast path first, L: the engine's\n"
        "way, the fast path in vector lanes for 512 queries at a time (lane kernels %s) and F for what it\n"
        "leaves open (0 with a minimum distance); alternating runs, medians of %d. hits: reported contacts\n"
        "(! when S, F and L differ in contacts or times). f-hit, f-miss:\n"
        "share of the queries past the filters that the fast path certifies / clears; l-open: share of them\n"
        "that L leaves to F; pieces: search pieces\n"
        "per query past the filters; toi sum: over the reported contacts.\n",
        mccd::detail::to_string(mccd::detail::lane_kernels().level), runs);
  } catch (const std::exception& e) {
    return mccd::bench::report_failure("bench_ccd", e);
  }
  return 0;
}
