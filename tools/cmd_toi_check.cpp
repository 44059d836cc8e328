// `mccd toi-check DIR`: one step of a scene in the Time-of-Impact data layout, checked against
// its exact ground truth (frames/, boxes/, mma_bool/).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <unordered_set>

#include <oneapi/tbb/info.h>

#include "args.h"
#include "command.h"
#include "toi_truth.h"
#include <mccd/core/orphans.h>
#include <mccd/core/scene.h>
#include <mccd/geometry/mesh_io.h>

namespace {

using namespace mccd;
using cli::read_truth_pairs;
using cli::TruthPairs;
namespace fs = std::filesystem;

std::uint64_t key(std::uint64_t a, std::uint64_t b) { return (a << 32) | b; }

struct KindReport {
  std::size_t listed = 0, truth = 0, found = 0, missed = 0, beyond = 0;
};

/// The true pairs of one kind: boxes file + matching truth file, as keys of global ids.
std::vector<std::uint64_t> true_pairs(const fs::path& boxes, const fs::path& truth, std::size_t& listed) {
  const TruthPairs t = read_truth_pairs(boxes, truth);
  listed = t.listed;
  std::vector<std::uint64_t> out;
  for (const auto& p : t.colliding) out.push_back(key(p[0], p[1]));
  return out;
}

fs::path find_one(const fs::path& dir, const std::string& suffix) {
  if (!fs::is_directory(dir)) throw Error(dir.string() + ": no such folder");
  std::vector<fs::path> hits;
  for (auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().size() >= suffix.size() &&
        e.path().filename().string().ends_with(suffix))
      hits.push_back(e.path());
  if (hits.size() != 1)
    throw Error(dir.string() + ": expected exactly one *" + suffix + " file, found " + std::to_string(hits.size()));
  return hits[0];
}

int toi_check(const std::vector<std::string>& args) {
  cli::Args a(args, {"method", "min-distance", "threads"}, {});
  if (a.positional().size() != 1) throw Error("usage: mccd toi-check DIR [--method ...]");
  const fs::path dir = a.positional()[0];
  const Method method = parse_method(a.get("method", "fbd").c_str());
  std::vector<std::string> frames;
  for (auto& e : fs::directory_iterator(dir / "frames"))
    if (e.path().extension() == ".ply") frames.push_back(e.path().string());
  std::sort(frames.begin(), frames.end());
  if (frames.size() != 2)
    throw Error((dir / "frames").string() + ": expected two .ply frames, found " + std::to_string(frames.size()));
  FrameSequence seq = read_frames(frames);
  const std::size_t nv = seq.mesh.num_vertices();
  SceneOptions opt;
  opt.min_distance = a.get_double("min-distance", 0.0);
  const long threads = a.get_int("threads", tbb::info::default_concurrency());
  if (threads < 1) throw Error("--threads must be at least 1");
  tbb::task_arena arena(static_cast<int>(threads));
  opt.arena = &arena;
  Scene scene({seq.mesh}, opt);
  const std::size_t ne = scene.topology().num_edges();
  std::printf("%s: %zu vertices, %zu triangles, %zu edges; step %s -> %s, method %s, %ld threads\n", dir.string().c_str(), nv,
              seq.mesh.num_faces(), ne, fs::path(frames[0]).filename().c_str(), fs::path(frames[1]).filename().c_str(),
              to_string(method), threads);

  std::size_t listed_vf = 0, listed_ee = 0;
  const auto vf_true = true_pairs(find_one(dir / "boxes", "vf.json"), find_one(dir / "mma_bool", "vf_mma_bool.json"), listed_vf);
  const auto ee_true = true_pairs(find_one(dir / "boxes", "ee.json"), find_one(dir / "mma_bool", "ee_mma_bool.json"), listed_ee);

  StepResult r = scene.step(seq.frames[0], seq.frames[1], method);
  std::unordered_set<std::uint64_t> got_vf, got_ee;
  for (const Contact& c : r.contacts) {
    if (c.kind == ContactKind::VertexFace)
      got_vf.insert(key(c.a, nv + ne + c.b));
    else
      got_ee.insert(key(nv + c.a, nv + c.b));
  }
  auto report = [](const char* kind, std::size_t listed, const std::vector<std::uint64_t>& truth,
                   const std::unordered_set<std::uint64_t>& got) {
    KindReport k;
    k.listed = listed;
    k.truth = truth.size();
    std::unordered_set<std::uint64_t> truth_set;
    for (auto t : truth) {
      // pairs may be listed in either order
      const std::uint64_t swapped = key(t & 0xffffffffu, t >> 32);
      truth_set.insert(t);
      truth_set.insert(swapped);
      if (got.count(t) || got.count(swapped))
        ++k.found;
      else
        ++k.missed;
    }
    for (auto g : got)
      if (!truth_set.count(g)) ++k.beyond;
    std::printf("  %s: %zu listed pairs, %zu true; reported %zu: found %zu, missed %zu (false negatives), %zu beyond the list\n",
                kind, k.listed, k.truth, got.size(), k.found, k.missed, k.beyond);
    return k;
  };
  const KindReport vf = report("vertex-face", listed_vf, vf_true, got_vf);
  const KindReport ee = report("edge-edge  ", listed_ee, ee_true, got_ee);
  const StepStats& s = r.stats;
  std::printf("  volume tests %llu (overlapping non-adjacent leaf pairs %llu), feature box tests %llu\n",
              (unsigned long long)s.volume_tests, (unsigned long long)s.leaf_pairs,
              (unsigned long long)s.feature_box_tests);
  std::printf("  elementary tests called: VF %llu, EE %llu; past their box and coplanarity filters: VF %llu, EE %llu\n",
              (unsigned long long)s.vf_tests, (unsigned long long)s.ee_tests, (unsigned long long)s.vf_ccd.root_tests,
              (unsigned long long)s.ee_ccd.root_tests);
  std::printf("  orphan set %zu VF + %zu EE pairs (%llu + %llu passed their box test); earliest toi %.9g\n",
              scene.orphan_vf_count(), scene.orphan_ee_count(), (unsigned long long)s.orphan_vf_tested,
              (unsigned long long)s.orphan_ee_tested, r.earliest_toi);
  const detail::StaticOrphanCounts so = detail::static_orphan_counts(scene.topology());
  std::printf("  (a static first-triangle assignment would leave %zu VF + %zu EE orphan pairs)\n", so.vf, so.ee);
  if (method == Method::Fbd)
    std::printf("  front %llu nodes (%.1f MB); the orphan set keeps %llu adjacent leaf pairs out of it (%.1f%% shorter)\n",
                (unsigned long long)s.front_size, s.front_bytes / 1e6, (unsigned long long)s.adjacent_leaf_pairs,
                100.0 * double(s.adjacent_leaf_pairs) / double(std::max<std::uint64_t>(s.front_size + s.adjacent_leaf_pairs, 1)));
  std::printf("  time %.3f s (update %.3f, refit %.3f, front %.3f, orphans %.3f)\n", s.t_total, s.t_update, s.t_refit,
              s.t_front, s.t_orphans);
  const std::size_t missed = vf.missed + ee.missed;
  std::printf("%s: %zu true pairs missed\n", missed ? "FAIL" : "OK", missed);
  return missed ? 1 : 0;
}

const cli::Command reg("toi-check", "toi-check DIR [--method bruteforce|traverse|phc|fbd] [--min-distance D] [--threads N]",
                       "runs one step of a Time-of-Impact data set scene and checks every true pair is reported",
                       toi_check);
}  // namespace
