// `mccd run FRAMES...` and `mccd demo`: a sequence of steps over frame files or a built-in
// scene, printing per step the contacts, the earliest time of impact and the statistics.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <oneapi/tbb/info.h>

#include "args.h"
#include "command.h"
#include <mccd/core/scene.h>
#include "fixtures/scenes.h"
#include <mccd/geometry/mesh_io.h>
#include <mccd/parallel/frame_pipeline.h>

namespace {

using namespace mccd;

struct Totals {
  std::uint64_t volume_tests = 0, vf_tests = 0, ee_tests = 0, contacts = 0, rebuilds = 0;
  std::uint64_t last_front = 0, last_adjacent = 0;  // at the last front build
  std::size_t steps = 0;
  double seconds = 0;
};

void print_header() {
  std::printf("%5s %9s %10s %12s %10s %10s %10s %9s %9s %4s %8s %8s\n", "step", "contacts", "earliest", "vol_tests",
              "vf_tests", "ee_tests", "front", "sprouted", "invalid", "rb", "orph_vf", "ms");
}

void print_row(std::size_t step, const StepResult& r) {
  const StepStats& s = r.stats;
  char toi[32];
  if (std::isinf(r.earliest_toi))
    std::snprintf(toi, sizeof toi, "-");
  else
    std::snprintf(toi, sizeof toi, "%.6f", r.earliest_toi);
  std::printf("%5zu %9zu %10s %12llu %10llu %10llu %10llu %9llu %9llu %4llu %8llu %8.2f\n", step, r.contacts.size(), toi,
              (unsigned long long)s.volume_tests, (unsigned long long)s.vf_tests, (unsigned long long)s.ee_tests,
              (unsigned long long)s.front_size, (unsigned long long)s.sprouted, (unsigned long long)s.invalidated,
              (unsigned long long)s.rebuilds, (unsigned long long)s.orphan_vf_tested, 1e3 * s.t_total);
}

/// Writes the contacts of every step as CSV, to a temporary renamed at the end.
class ContactWriter {
 public:
  explicit ContactWriter(std::string path) : path_(std::move(path)) {
    if (path_.empty()) return;
    tmp_ = path_ + ".tmp";
    out_.open(tmp_);
    if (!out_) throw Error(path_ + ": cannot open for writing");
    out_ << "step,kind,mesh_a,a,mesh_b,b,a_v0,a_v1,b_v0,b_v1,toi\n";
    out_.precision(17);
  }
  ~ContactWriter() {
    if (!tmp_.empty() && !done_) {
      out_.close();
      std::filesystem::remove(tmp_);
    }
  }
  void add(std::size_t step, const StepResult& r) {
    if (path_.empty()) return;
    for (const Contact& c : r.contacts) {
      out_ << step << ',' << (c.kind == ContactKind::VertexFace ? "vf" : "ee") << ',' << c.mesh_a << ',' << c.a << ','
           << c.mesh_b << ',' << c.b << ',';
      if (c.kind == ContactKind::EdgeEdge)
        out_ << c.a_vertices[0] << ',' << c.a_vertices[1] << ',' << c.b_vertices[0] << ',' << c.b_vertices[1];
      else
        out_ << ",,,";
      out_ << ',' << c.toi << '\n';
    }
  }
  void finish() {
    if (path_.empty()) return;
    out_.close();
    if (!out_) throw Error(path_ + ": write failed");
    std::filesystem::rename(tmp_, path_);
    done_ = true;
  }

 private:
  std::string path_, tmp_;
  std::ofstream out_;
  bool done_ = false;
};

/// Runs the frames of `source` after `first` through the frame pipeline (reading, stepping and
/// writing overlap), with `substeps` linear sub-steps per interval.
Totals run_sequence(Scene& scene, std::vector<Positions> first, const FrameSource& source, int substeps,
                    Method method, ContactWriter& writer, bool quiet) {
  Totals t;
  if (!quiet) print_header();
  PipelineOptions po;
  po.substeps = substeps;
  po.method = method;
  run_frame_pipeline(
      scene, std::move(first), source,
      [&](const PipelineStep& s) {
        const StepResult& r = s.result;
        if (!quiet) print_row(s.index, r);
        writer.add(s.index, r);
        t.volume_tests += r.stats.volume_tests;
        t.vf_tests += r.stats.vf_tests;
        t.ee_tests += r.stats.ee_tests;
        t.contacts += r.contacts.size();
        t.rebuilds += r.stats.rebuilds;
        if (r.stats.rebuilds) {
          t.last_front = r.stats.front_size;
          t.last_adjacent = r.stats.adjacent_leaf_pairs;
        }
        t.seconds += r.stats.t_total;
        ++t.steps;
      },
      po);
  return t;
}

/// A source over frames already in memory (frames[1], frames[2], ...).
FrameSource from_memory(const std::vector<std::vector<Positions>>& frames) {
  auto next = std::make_shared<std::size_t>(1);
  return [&frames, next](std::vector<Positions>& out) {
    if (*next >= frames.size()) return false;
    out = frames[(*next)++];
    return true;
  };
}

void print_totals(const Scene& scene, const Totals& t, Method method) {
  const std::size_t steps = t.steps;
  std::printf("total over %zu steps (%s): contacts %llu, volume tests %llu, VF tests %llu, EE tests %llu, "
              "front rebuilds %llu, %.3f s\n",
              steps, to_string(method), (unsigned long long)t.contacts, (unsigned long long)t.volume_tests,
              (unsigned long long)t.vf_tests, (unsigned long long)t.ee_tests, (unsigned long long)t.rebuilds, t.seconds);
  std::printf("orphan set: %zu VF pairs, %zu EE pairs; BVH depth %zu\n", scene.orphan_vf_count(),
              scene.orphan_ee_count(), scene.bvh_depth());
  if (t.rebuilds)
    std::printf("last front build: %llu nodes; the orphan set kept %llu adjacent leaf pairs out (%.1f%% shorter)\n",
                (unsigned long long)t.last_front, (unsigned long long)t.last_adjacent,
                100.0 * double(t.last_adjacent) / double(std::max<std::uint64_t>(t.last_front + t.last_adjacent, 1)));
}

SceneOptions scene_options(const cli::Args& a) {
  SceneOptions o;
  o.method = parse_method(a.get("method", "fbd").c_str());
  o.min_distance = a.get_double("min-distance", 0.0);
  o.rebuild_sprout_ratio = a.get_double("rebuild-sprout", 0.30);
  o.rebuild_invalid_ratio = a.get_double("rebuild-invalid", 0.45);
  o.volume = parse_volume(a.get("volume", "kdop18").c_str());
  return o;
}

int run_cmd(const std::vector<std::string>& args) {
  cli::Args a(args, {"method", "contacts", "substeps", "scene", "size", "frames", "min-distance", "volume",
                     "rebuild-sprout", "rebuild-invalid", "threads"},
              {"quiet"});
  const SceneOptions opt = scene_options(a);
  const long substeps = a.get_int("substeps", 1);
  if (substeps < 1) throw Error("--substeps must be at least 1");
  ContactWriter writer(a.get("contacts"));
  const long threads = a.get_int("threads", tbb::info::default_concurrency());
  if (threads < 1) throw Error("--threads must be at least 1");
  tbb::task_arena arena(static_cast<int>(threads));
  SceneOptions opt_arena = opt;
  opt_arena.arena = &arena;
  Totals t;
  if (a.has("scene")) {
    if (!a.positional().empty()) throw Error("give either frame files or --scene, not both");
    AnimatedScene s = make_scene(a.get("scene"), int(a.get_int("size", 4)), int(a.get_int("frames", 31)));
    std::printf("scene %s: %zu meshes, %zu triangles, %zu frames\n", s.name.c_str(), s.meshes.size(),
                s.num_triangles(), s.frames.size());
    Scene scene(s.meshes, opt_arena);
    t = run_sequence(scene, s.frames[0], from_memory(s.frames), int(substeps), opt.method, writer, a.has("quiet"));
    writer.finish();
    print_totals(scene, t, opt.method);
  } else {
    if (a.positional().empty()) throw Error("no frames given (files, a pattern like frame%03d.ply, or --scene)");
    // Frames are read one at a time, ahead of the step that needs them (the frame pipeline).
    const std::vector<std::string> paths = frame_paths(a.positional());
    if (paths.size() < 2) throw Error("need at least two frames, got " + std::to_string(paths.size()));
    TriMesh first = read_mesh(paths[0]);
    std::printf("%zu frames of %s: %zu vertices, %zu triangles\n", paths.size(), paths[0].c_str(),
                first.num_vertices(), first.num_faces());
    Scene scene({first}, opt_arena);
    std::size_t next = 1;
    FrameSource source = [&](std::vector<Positions>& out) {
      if (next >= paths.size()) return false;
      out.assign(1, read_frame(paths[next], next, first, paths[0]));
      ++next;
      return true;
    };
    t = run_sequence(scene, std::vector<Positions>{first.vertices}, source, int(substeps), opt.method, writer, a.has("quiet"));
    writer.finish();
    print_totals(scene, t, opt.method);
  }
  return 0;
}

int demo_cmd(const std::vector<std::string>& args) {
  cli::Args a(args, {"size", "frames"}, {});
  AnimatedScene s = make_scene("cloth", int(a.get_int("size", 8)), int(a.get_int("frames", 31)));
  std::printf("built-in scene: a cloth of %zu triangles folding onto itself, %zu frames\n", s.num_triangles(),
              s.frames.size());
  Totals per[2];
  const Method methods[2] = {Method::Traverse, Method::Fbd};
  std::vector<std::vector<Contact>> last(2);
  ContactWriter none("");
  for (int i = 0; i < 2; ++i) {
    Scene scene(s.meshes);
    if (i == 1) std::printf("\nmethod fbd, per step:\n");
    per[i] = run_sequence(scene, s.frames[0], from_memory(s.frames), 1, methods[i], none, i == 0);
    if (i == 1) print_totals(scene, per[i], methods[i]);
  }
  std::printf("\ntraverse: %llu volume tests, %.3f s; fbd: %llu volume tests (%.1f%% fewer), %.3f s\n",
              (unsigned long long)per[0].volume_tests, per[0].seconds, (unsigned long long)per[1].volume_tests,
              100.0 * (1.0 - double(per[1].volume_tests) / double(std::max<std::uint64_t>(per[0].volume_tests, 1))),
              per[1].seconds);
  if (per[0].contacts != per[1].contacts) {
    std::printf("error: the methods disagree (%llu vs %llu contacts)\n", (unsigned long long)per[0].contacts,
                (unsigned long long)per[1].contacts);
    return 1;
  }
  return 0;
}

const cli::Command reg_run("run",
                           "run FRAMES... | --scene cloth|spheres|random|tube [--size K] [--frames N]  [--method "
                           "bruteforce|traverse|phc|fbd] [--substeps K] [--contacts FILE.csv] [--min-distance D] "
                           "[--volume kdop18|aabb] [--threads N] [--quiet]",
                           "steps through frames (files, a printf pattern, or a built-in scene) and prints per-step "
                           "contacts, earliest time of impact and statistics",
                           run_cmd);
const cli::Command reg_demo("demo", "demo [--size K] [--frames N]",
                            "runs the built-in folding-cloth scene with traversal and front tracking and compares them",
                            demo_cmd);
}  // namespace
