#include "run_driver.h"

#include <csignal>
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/error.h>
#include <mccd/parallel/frame_pipeline.h>

#include "interrupt.h"
#include "options.h"
#include "progress.h"
#include "run_table.h"
#include "snapshot.h"

namespace mccd::cli {

namespace {

/// The output files of a run, finished together.
struct Outputs {
  std::unique_ptr<ContactsFile> contacts;
  std::unique_ptr<StatsFile> stats;

  std::vector<StreamedFile*> files() const {
    std::vector<StreamedFile*> out;
    if (contacts) out.push_back(contacts.get());
    if (stats) out.push_back(stats.get());
    return out;
  }
  void add(std::size_t step, std::size_t substep, const StepResult& r) {
    if (contacts) contacts->add(step, substep, r);
    if (stats) stats->add(step, substep, r);
  }
  /// After an error or a signal: keeps (marked incomplete) or removes each file, and says so
  /// on stderr (unless silent).
  void stop(Partial partial, const std::string& why, std::size_t steps, const std::string& command,
            bool silent) noexcept {
    for (StreamedFile* f : files()) {
      if (f->done()) continue;
      f->stop(partial, why, steps);
      if (silent) continue;
      if (partial == Partial::Keep)
        std::fprintf(stderr, "%s: %s keeps the %zu finished step%s, marked incomplete\n", command.c_str(),
                     f->path().c_str(), steps, steps == 1 ? "" : "s");
      else
        std::fprintf(stderr, "%s: %s not written (--partial remove)\n", command.c_str(), f->path().c_str());
    }
  }
};

const char* signal_name(int sig) {
  return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : sig == SIGHUP ? "SIGHUP" : "a signal";
}

nlohmann::json summary_json(const RunTotals& t, double wall) {
  return {{"summary",
           {{"steps", t.steps},
            {"steps_with_contacts", t.steps_with_contacts},
            {"vf_contacts", t.vf},
            {"ee_contacts", t.ee},
            {"first_impact", t.vf + t.ee ? nlohmann::json(t.first) : nlohmann::json(nullptr)},
            {"first_impact_step", t.vf + t.ee ? nlohmann::json(t.first_step) : nlohmann::json(nullptr)},
            {"step_seconds", t.step_seconds},
            {"wall_seconds", wall}}}};
}

/// Draws the picture and the coloured mesh of the chosen moment.
void write_pictures(const RunInput& input, const RunSettings& st, std::optional<Snapshot> snap) {
  if (st.image.empty() && st.colored.empty()) return;
  if (!snap) {
    snap = Snapshot{0, 0, st.substeps, 0.0, {}};
    if (!st.silent) std::printf("no contact to show: the picture is of frame 0\n");
  }
  std::vector<Positions> start;
  if (snap->step == 0)
    for (const TriMesh& m : input.meshes) start.push_back(m.vertices);
  else
    start = input.frame(snap->step);
  const std::vector<Positions> end = input.frame(snap->step + 1);
  const std::vector<ViewMesh> view = snapshot_view(input.meshes, start, end, *snap);
  CameraRequest camera = st.camera.empty() ? CameraRequest{} : parse_camera(st.camera);
  if (!camera.up) camera.up = st.up;
  const std::string when = "step " + std::to_string(snap->step) + " at frame time " +
                           impact_text(frame_time(snap->step, snap->substep, snap->substeps, snap->t)) + ", " +
                           grouped(highlighted_faces(view)) + " triangles highlighted";
  if (!st.image.empty()) {
    const Image image = render_snapshot(view, st.image_width, st.image_height, camera);
    {
      // a signal waits for the file to be complete, so that no temporary is left behind
      std::lock_guard<std::mutex> lock(interrupt_mutex());
      write_png(st.image, image);
    }
    if (!st.silent) std::printf("picture: %s (%s)\n", st.image.c_str(), when.c_str());
  }
  if (!st.colored.empty()) {
    std::lock_guard<std::mutex> lock(interrupt_mutex());
    write_snapshot_ply(st.colored, view);
    if (!st.silent) std::printf("coloured mesh: %s (%s)\n", st.colored.c_str(), when.c_str());
  }
}

}  // namespace

int run_frames(const RunInput& input, const RunSettings& st, const std::string& command) {
  const auto wall_start = std::chrono::steady_clock::now();
  if (input.frames < 2) throw Error("need at least two frames, got " + std::to_string(input.frames));
  const std::size_t steps = input.frames - 1;
  const int K = st.substeps;
  if (st.image_step && *st.image_step >= steps)
    throw Error("--image-step " + std::to_string(*st.image_step) + ": the run has steps 0 to " +
                std::to_string(steps - 1));
  if (!st.camera.empty()) (void)parse_camera(st.camera);
  // every output's folder exists before any work (the picture is only written at the end)
  for (const std::string* path : {&st.contacts, &st.stats, &st.image, &st.colored}) {
    if (path->empty()) continue;
    const std::filesystem::path folder = std::filesystem::absolute(*path).parent_path();
    std::error_code ec;
    if (!std::filesystem::is_directory(folder, ec))
      throw Error(*path + ": cannot write: no such folder " + folder.string());
  }
  if (!st.contacts.empty()) check_extension("--contacts", st.contacts, {".csv", ".json"});
  if (!st.stats.empty()) check_extension("--stats", st.stats, {".json"});
  std::vector<Positions> first;
  for (const TriMesh& m : input.meshes) first.push_back(m.vertices);
  check_min_distance(st.scene.min_distance, first);

  tbb::task_arena arena(st.threads);
  SceneOptions so = st.scene;
  so.arena = &arena;
  // Frame 1 is read while the scene is built (its parallel set-up has the other threads); an
  // error reading it is reported where the pipeline would have met it.
  std::optional<std::vector<Positions>> frame1;
  std::string frame1_error;
  tbb::task_group prefetch;
  if (input.frames > 1)
    arena.execute([&] {
      prefetch.run([&] {
        try {
          frame1 = input.frame(1);
        } catch (const std::exception& e) {
          frame1_error = e.what();
        }
      });
    });
  struct Join {  // waits for the read however this scope is left
    tbb::task_arena& arena;
    tbb::task_group& group;
    ~Join() { arena.execute([&] { group.wait(); }); }
  } join_prefetch{arena, prefetch};
  Scene scene(input.meshes, so);  // validates the meshes and the options before any file exists
  arena.execute([&] { prefetch.wait(); });
  std::size_t nv = 0, nf = 0;
  for (const TriMesh& m : input.meshes) nv += m.num_vertices(), nf += m.num_faces();
  if (!st.silent) {
    std::printf("%s: %zu frames, %s vertices, %s triangles%s; method %s, %d thread%s", input.description.c_str(),
                input.frames, grouped(nv).c_str(), grouped(nf).c_str(),
                input.meshes.size() > 1 ? (" in " + std::to_string(input.meshes.size()) + " meshes").c_str() : "",
                to_string(st.scene.method), st.threads, st.threads == 1 ? "" : "s");
    if (K > 1) std::printf(", %d sub-steps per step", K);
    std::printf("\n");
  }

  const RunFacts facts{input.description, input.frames, K, to_string(st.scene.method), st.scene.min_distance};
  Outputs out;
  if (!st.contacts.empty()) out.contacts = std::make_unique<ContactsFile>(st.contacts, facts, input.meshes);
  if (!st.stats.empty()) out.stats = std::make_unique<StatsFile>(st.stats, facts);

  const bool quiet = st.quiet || st.silent;
  ProgressBar bar(!quiet && ProgressBar::stderr_is_terminal(), steps);
  const RunTable table(st.verbose);
  if (!quiet) {
    table.print_legend();
    table.print_header();
  }
  StepAccumulator acc(K);
  RunTotals totals;
  SnapshotPicker picker(st.image_step, K);
  std::size_t steps_done = 0;

  const InterruptCleanup on_signal([&](int sig) {
    bar.erase();
    std::fflush(stdout);
    std::fprintf(stderr, "%s: interrupted by %s after %zu of %zu steps\n", command.c_str(), signal_name(sig),
                 steps_done, steps);
    out.stop(st.partial,
             std::string("interrupted by ") + signal_name(sig) + " after " + std::to_string(steps_done) + " of " +
                 std::to_string(steps) + " steps",
             steps_done, command, st.silent);
  });

  // A frame that cannot be read ends the sequence there, so that every step before it is
  // still stepped and written; the error is raised once they are.
  std::size_t next = 1;
  std::string source_error;
  const FrameSource source = [&](std::vector<Positions>& frame) {
    if (next >= input.frames) return false;
    try {
      if (next == 1 && !frame1_error.empty()) throw Error(frame1_error);
      frame = next == 1 && frame1 ? std::move(*frame1) : input.frame(next);
    } catch (const std::exception& e) {
      source_error = e.what();
      return false;
    }
    ++next;
    return true;
  };
  const StepSink sink = [&](const PipelineStep& ps) {
    const std::size_t s = ps.index - 1, k = s / std::size_t(K), j = s % std::size_t(K);
    std::lock_guard<std::mutex> lock(interrupt_mutex());
    out.add(k, j, ps.result);
    picker.offer(k, j, ps.result);
    if (acc.add(k, j, ps.result)) {
      totals.add(acc.row());
      steps_done = k + 1;
      if (!quiet) bar.print_above([&] { table.print_row(acc.row()); });
      if (st.on_step) st.on_step(acc.row());
    }
    bar.update(double(k) + double(j + 1) / K, totals.vf + totals.ee);
  };
  PipelineOptions po;
  po.substeps = K;
  po.method = st.scene.method;
  try {
    arena.execute([&] { run_frame_pipeline(scene, first, source, sink, po); });
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(interrupt_mutex());
    bar.erase();
    std::fflush(stdout);
    out.stop(st.partial, e.what(), steps_done, command, st.silent);
    throw;
  }
  bar.erase();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  if (!source_error.empty()) {
    {
      std::lock_guard<std::mutex> lock(interrupt_mutex());
      std::fflush(stdout);
      out.stop(st.partial, source_error, steps_done, command, st.silent);
    }
    if (!st.silent) print_summary(totals, next, to_string(st.scene.method), st.threads, wall);
    std::fflush(stdout);
    throw Error(source_error);
  }
  {
    std::lock_guard<std::mutex> lock(interrupt_mutex());
    for (StreamedFile* f : out.files()) f->finish(steps, summary_json(totals, wall));
  }
  if (!st.silent) print_summary(totals, input.frames, to_string(st.scene.method), st.threads, wall);
  write_pictures(input, st, picker.chosen());
  return totals.vf + totals.ee > 0 && !st.exit_zero ? kExitFound : kExitClean;
}

}  // namespace mccd::cli
