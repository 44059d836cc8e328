// `mccd toi-check DIR`: one step of a scene in the Time-of-Impact data layout, checked against
// its exact ground truth (frames/, boxes/, mma_bool/).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include <CLI/App.hpp>

#include "command.h"
#include "options.h"
#include "toi_truth.h"
#include <mccd/core/canonical_rule_orphans.h>
#include <mccd/parallel/scene.h>
#include <mccd/geometry/lane_masks.h>
#include <mccd/geometry/error.h>
#include <mccd/geometry/mesh_io.h>

namespace {

using namespace mccd;
namespace fs = std::filesystem;

std::uint64_t key(std::uint64_t a, std::uint64_t b) { return (a << 32) | b; }

struct KindReport {
  std::size_t listed = 0, truth = 0, found = 0, missed = 0, beyond = 0;
};

/// The true pairs of one kind: boxes file + matching truth file, as keys of global ids.
std::vector<std::uint64_t> true_pairs(const fs::path& boxes, const fs::path& truth, std::size_t& listed) {
  const cli::TruthPairs t = cli::read_truth_pairs(boxes, truth);
  listed = t.listed;
  std::vector<std::uint64_t> out;
  out.reserve(t.colliding.size());
  for (const auto& p : t.colliding) out.push_back(key(p[0], p[1]));
  return out;
}

fs::path find_one(const fs::path& dir, const std::string& suffix) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error(dir.string() + ": no such folder");
  std::vector<fs::path> hits;
  for (auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().size() >= suffix.size() &&
        e.path().filename().string().ends_with(suffix))
      hits.push_back(e.path());
  if (hits.size() != 1)
    throw Error(dir.string() + ": expected exactly one *" + suffix + " file, found " + std::to_string(hits.size()));
  return hits[0];
}

struct ToiOptions {
  std::string dir;
  Method method = Method::Fbd;
  double min_distance = 0.0;
  int threads = 1;
  BvhBuild bvh = BvhBuild::Sah;
  unsigned leaf_size = 0;
  Representatives rule = Representatives::Default;
  bool self_culling = true;
  bool static_orphans = false;
};

/// The two .ply frames of a scene folder, refused with a message naming the folder when the
/// layout is not there.
std::vector<std::string> scene_frames(const fs::path& dir) {
  const char* layout = " (a Time-of-Impact scene folder holds frames/, boxes/ and mma_bool/)";
  std::error_code ec;
  if (!fs::exists(dir, ec)) throw Error(dir.string() + ": no such folder");
  if (!fs::is_directory(dir, ec)) throw Error(dir.string() + ": not a folder" + layout);
  const fs::path frames_dir = dir / "frames";
  if (!fs::is_directory(frames_dir, ec)) throw Error(frames_dir.string() + ": no such folder" + layout);
  std::vector<std::string> frames;
  for (fs::directory_iterator it(frames_dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".ply") frames.push_back(it->path().string());
  if (ec) throw Error(frames_dir.string() + ": cannot list: " + ec.message());
  std::sort(frames.begin(), frames.end());
  if (frames.size() != 2)
    throw Error(frames_dir.string() + ": expected two .ply frames, found " + std::to_string(frames.size()));
  return frames;
}

int toi_check(const ToiOptions& a) {
  const fs::path dir = a.dir;
  const Method method = a.method;
  const std::vector<std::string> frames = scene_frames(dir);
  // the truth first: a scene folder without it is refused before any work
  std::size_t listed_vf = 0, listed_ee = 0;
  const auto vf_true = true_pairs(find_one(dir / "boxes", "vf.json"), find_one(dir / "mma_bool", "vf_mma_bool.json"), listed_vf);
  const auto ee_true = true_pairs(find_one(dir / "boxes", "ee.json"), find_one(dir / "mma_bool", "ee_mma_bool.json"), listed_ee);
  FrameSequence seq = read_frames(frames);
  const std::size_t nv = seq.mesh.num_vertices();
  SceneOptions opt;
  cli::check_min_distance(a.min_distance, {seq.frames[0]});
  opt.min_distance = a.min_distance;
  opt.bvh = a.bvh;
  opt.leaf_size = a.leaf_size;
  opt.representatives = a.rule;
  opt.self_culling = a.self_culling;
  const int threads = a.threads;
  tbb::task_arena arena(static_cast<int>(threads));
  opt.arena = &arena;
  Scene scene({seq.mesh}, opt);
  const std::size_t ne = scene.topology().num_edges();
  std::printf("%s: %zu vertices, %zu triangles, %zu edges; step %s -> %s, method %s, %d threads\n", dir.string().c_str(), nv,
              seq.mesh.num_faces(), ne, fs::path(frames[0]).filename().c_str(), fs::path(frames[1]).filename().c_str(),
              to_string(method), threads);

  StepResult r = scene.step(seq.frames[0], seq.frames[1], method);
  // Reported and true pairs as sorted keys: 8 bytes a pair (hash sets of them held 13 MB at the
  // end of the cloth-ball step).
  std::vector<std::uint64_t> got_vf, got_ee;
  for (const Contact& c : r.contacts) {
    if (c.kind == ContactKind::VertexFace)
      got_vf.push_back(key(c.a, nv + ne + c.b));
    else
      got_ee.push_back(key(nv + c.a, nv + c.b));
  }
  r.contacts = {};  // counted; what is left of the step is its statistics
  auto report = [](const char* kind, std::size_t listed, const std::vector<std::uint64_t>& truth,
                   std::vector<std::uint64_t>& got) {
    std::sort(got.begin(), got.end());
    got.erase(std::unique(got.begin(), got.end()), got.end());
    // Pairs may be listed in either order: both sides compared as (smaller id, larger id),
    // sorted, in one merge each way.
    auto unordered = [](std::uint64_t k) {
      const std::uint64_t a = k >> 32, b = k & 0xffffffffu;
      return a <= b ? k : key(b, a);
    };
    auto sorted_unordered = [&](const std::vector<std::uint64_t>& keys) {
      std::vector<std::uint64_t> out(keys.size());
      std::transform(keys.begin(), keys.end(), out.begin(), unordered);
      std::sort(out.begin(), out.end());
      return out;
    };
    const std::vector<std::uint64_t> got_u = sorted_unordered(got), truth_u = sorted_unordered(truth);
    // How many of `keys` (sorted) are in `in` (sorted).
    auto count_in = [](const std::vector<std::uint64_t>& keys, const std::vector<std::uint64_t>& in) {
      std::size_t n = 0;
      auto it = in.begin();
      for (std::uint64_t k : keys) {
        while (it != in.end() && *it < k) ++it;
        n += it != in.end() && *it == k;
      }
      return n;
    };
    KindReport k;
    k.listed = listed;
    k.truth = truth.size();
    k.found = count_in(truth_u, got_u);
    k.missed = truth.size() - k.found;
    k.beyond = got.size() - count_in(got_u, truth_u);
    std::printf("  %s: %zu listed pairs, %zu true; reported %zu: found %zu, missed %zu (false negatives), %zu beyond the list\n",
                kind, k.listed, k.truth, got.size(), k.found, k.missed, k.beyond);
    return k;
  };
  const KindReport vf = report("vertex-face", listed_vf, vf_true, got_vf);
  const KindReport ee = report("edge-edge  ", listed_ee, ee_true, got_ee);
  const StepStats& s = r.stats;
  const bool leaf_rule = resolved_representatives(scene.options()) == Representatives::Leaf;
  if (leaf_rule)
    std::printf("  volume tests %llu, leaf pairs meeting in some quarter %llu, feature-pair volume tests (pairs whose "
                "coarse volumes meet) %llu, removed by the coplanarity filter: VF %llu, EE %llu\n",
                (unsigned long long)s.volume_tests, (unsigned long long)s.leaf_pairs,
                (unsigned long long)s.feature_box_tests, (unsigned long long)s.vf_filtered,
                (unsigned long long)s.ee_filtered);
  else
    std::printf("  volume tests %llu, triangle-pair tests inside leaf pairs %llu (overlapping non-adjacent triangle "
                "pairs %llu), feature-pair volume tests %llu, removed by the coplanarity filter: VF %llu, EE %llu\n",
                (unsigned long long)s.volume_tests, (unsigned long long)s.triangle_tests,
                (unsigned long long)s.leaf_pairs, (unsigned long long)s.feature_box_tests,
                (unsigned long long)s.vf_filtered, (unsigned long long)s.ee_filtered);
  std::printf("  elementary tests called: VF %llu, EE %llu (%.2f per true pair found); past their box and coplanarity "
              "filters: VF %llu, EE %llu\n",
              (unsigned long long)s.vf_tests, (unsigned long long)s.ee_tests,
              double(s.vf_tests + s.ee_tests) / double(std::max<std::size_t>(vf.found + ee.found, 1)),
              (unsigned long long)s.vf_ccd.root_tests, (unsigned long long)s.ee_ccd.root_tests);
  if (leaf_rule)
    std::printf("  representatives: leaf (every vertex and edge tested from the BVH leaf of its first triangle, no "
                "orphan set); lane kernels %s; earliest toi %.9g\n",
                detail::to_string(detail::lane_kernels().level), r.earliest_toi);
  else
    std::printf("  representatives: canonical; orphan set %zu VF + %zu EE pairs (%llu + %llu passed their box test); "
                "earliest toi %.9g\n",
                scene.orphan_vf_count(), scene.orphan_ee_count(), (unsigned long long)s.orphan_vf_tested,
                (unsigned long long)s.orphan_ee_tested, r.earliest_toi);
  if (a.static_orphans) {
    const detail::StaticOrphanCounts so = detail::static_orphan_counts(scene.topology());
    std::printf("  (a static first-triangle assignment would leave %zu VF + %zu EE orphan pairs)\n", so.vf, so.ee);
  }
  if (method == Method::Fbd) {
    std::printf("  front %llu nodes (%.1f MB)", (unsigned long long)s.front_size, s.front_bytes / 1e6);
    if (!leaf_rule)
      std::printf("; the orphan set keeps %llu adjacent leaf pairs out of it (%.1f%% shorter)",
                  (unsigned long long)s.adjacent_leaf_pairs,
                  100.0 * double(s.adjacent_leaf_pairs) /
                      double(std::max<std::uint64_t>(s.front_size + s.adjacent_leaf_pairs, 1)));
    std::printf("\n");
  }
  std::printf("  time %.3f s (update %.3f, refit %.3f, front %.3f, %s %.3f)\n", s.t_total, s.t_update, s.t_refit,
              s.t_front, leaf_rule ? "self" : "orphans", s.t_self);
  const std::size_t missed = vf.missed + ee.missed;
  std::printf("%s: %zu true pairs missed\n", missed ? "FAIL" : "OK", missed);
  return missed ? 1 : 0;
}

const cli::Command reg(
    "toi-check", "run one step of a Time-of-Impact data set scene and check that every true pair is reported", 40,
    [](CLI::App& app) -> cli::Runner {
      auto o = std::make_shared<ToiOptions>();
      app.add_option("DIR", o->dir,
                     "a scene folder: frames/ (the two .ply frames of the step), boxes/ (*vf.json, *ee.json: "
                     "listed pairs) and mma_bool/ (*vf_mma_bool.json, *ee_mma_bool.json: their exact truth)")
          ->required()
          ->type_name("DIR");
      cli::add_method_option(app, o->method);
      cli::add_min_distance_option(app, o->min_distance, "; at most 1% of the scene's bounding-box diagonal");
      cli::add_threads_option(app, o->threads);
      cli::add_bvh_options(app, o->bvh, o->leaf_size, o->rule, o->self_culling);
      app.add_flag("--static-orphans", o->static_orphans,
                   "also count the orphan pairs a static (first-triangle) representative rule would leave, for "
                   "comparison with the canonical rule (takes a while on large scenes)");
      app.footer("Prints, per kind, the listed and true pairs and how many were found, missed and reported "
                 "beyond the list; the volume, feature-pair and elementary test counts; the representative rule "
                 "(with the canonical rule, its orphan set) and the front; and the step's time as 'time <seconds> s "
                 "(update, refit, front, self or orphans)': self / orphans is the stage of the pairs no front node "
                 "holds.\n"
                 "Exit status: 0 every true pair found, 1 any true pair missed, 2 usage or input error.");
      return [o] { return toi_check(*o); };
    });
}  // namespace
