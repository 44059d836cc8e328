#include "run_driver.h"

#include <chrono>
#include <csignal>
#include <filesystem>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>
#include <type_traits>

#include <nlohmann/json.hpp>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/error.h>
#include <mccd/geometry/large_allocator.h>
#include <mccd/parallel/frame_pipeline.h>

#include "interrupt.h"
#include "mpi/cluster.h"
#include "options.h"
#include "progress.h"
#include "run_table.h"
#include "snapshot.h"

namespace mccd::cli {

namespace {

/// A copy of the meshes, their arrays' pages backed in one call each (detail::backed_copy)
/// rather than faulted in one by one (several times dearer in a virtual machine).
std::vector<TriMesh> backed_copy(const std::vector<TriMesh>& meshes) {
  std::vector<TriMesh> out;
  for (const TriMesh& m : meshes)
    out.push_back({detail::backed_copy(m.vertices), detail::backed_copy(m.faces), m.name});
  return out;
}

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
  /// on stderr (unless muted).
  void stop(Partial partial, const std::string& why, std::size_t steps, const std::string& command,
            bool mute = false) noexcept {
    for (StreamedFile* f : files()) {
      if (f->done()) continue;
      f->stop(partial, why, steps);
      if (mute) continue;
      if (partial == Partial::Keep)
        std::fprintf(stderr, "%s: %s keeps the %zu finished step%s, marked incomplete\n", command.c_str(),
                     f->path().c_str(), steps, steps == 1 ? "" : "s");
      else
        std::fprintf(stderr, "%s: %s not written (--partial remove)\n", command.c_str(), f->path().c_str());
    }
  }
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

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

/// The caption of the picture of `snap`: what was run; the step (its frames), the sub-step
/// (whose contacts are shown) and the frame time; the contacts shown.
std::vector<std::string> caption(const RunInput& input, const FrameNames& names, const Snapshot& snap, bool any,
                                 std::size_t highlighted) {
  std::string when = "step " + std::to_string(snap.step) + " (" + names.step(snap.step) + ")";
  if (snap.substeps > 1)
    when += ", sub-step " + std::to_string(snap.substep + 1) + " of " + std::to_string(snap.substeps) + ",";
  when += " at frame time " + impact_text(frame_time(snap.step, snap.substep, snap.substeps, snap.t));
  std::string what;
  if (!any) {
    what = "no contact in the run: its first frame is shown";
  } else if (snap.contacts.empty()) {
    what = "no contact in this step: its start is shown";
  } else {
    std::size_t vf = 0;
    for (const Contact& c : snap.contacts) vf += c.kind == ContactKind::VertexFace;
    what = "contacts shown: " + grouped(snap.contacts.size()) + " (" + grouped(vf) + " vertex-face, " +
           grouped(snap.contacts.size() - vf) + " edge-edge), " + grouped(highlighted) + " triangles highlighted";
  }
  return {input.description, when, what};
}

/// Whether the run draws a picture or writes a coloured mesh of its snapshot.
bool wants_pictures(const RunSettings& st) { return !st.image.empty() || !st.colored.empty(); }

/// Draws the picture and the coloured mesh of the chosen moment.
void write_pictures(const RunInput& input, const RunSettings& st, const FrameNames& names, std::optional<Snapshot> snap) {
  if (!wants_pictures(st)) return;
  const bool any = snap.has_value();
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
    bool keyed = false;
    const Image image = render_snapshot(view, st.image_width, st.image_height, camera,
                                        caption(input, names, *snap, any, highlighted_faces(view)), &keyed);
    {
      // a signal waits for the file to be complete, so that no temporary is left behind
      std::lock_guard<std::mutex> lock(interrupt_mutex());
      write_image(st.image, image);
    }
    if (!st.mute)
      std::printf("picture: %s (%s%s)\n", st.image.c_str(), when.c_str(),
                  keyed ? "" : "; no caption or legend: too small for them");
  }
  if (!st.colored.empty()) {
    std::lock_guard<std::mutex> lock(interrupt_mutex());
    write_snapshot_ply(st.colored, view);
    if (!st.mute) std::printf("coloured mesh: %s (%s)\n", st.colored.c_str(), when.c_str());
  }
}


/// The message tags of a split run: a rank's range of results; rank 0's "all written".
constexpr int kRangeTag = 3501, kDoneTag = 3502;

static_assert(std::is_trivially_copyable_v<Contact> && std::is_trivially_copyable_v<StepStats>,
              "a step's result travels between ranks as bytes");

/// Bytes appended and read back in the same order (all ranks run the same build).
struct WireWriter {
  std::string bytes;
  template <class T>
  void put(const T& v) {
    bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void put_text(const std::string& s) {
    put<std::uint64_t>(s.size());
    bytes += s;
  }
};

struct WireReader {
  const std::string& bytes;
  std::size_t at = 0;
  bool done() const { return at >= bytes.size(); }
  template <class T>
  T get() {
    if (at + sizeof(T) > bytes.size()) throw Error("a rank's message ends early");
    T v;
    std::memcpy(&v, bytes.data() + at, sizeof v);
    at += sizeof v;
    return v;
  }
  std::string get_text() {
    const auto n = get<std::uint64_t>();
    if (at + n > bytes.size()) throw Error("a rank's message ends early");
    std::string s = bytes.substr(at, n);
    at += n;
    return s;
  }
};

/// The first step of rank `r`'s range when `steps` are split among `R` ranks.
std::size_t range_begin(std::size_t steps, int r, int R) { return steps * std::size_t(r) / std::size_t(R); }

/// A rank other than 0 of a split run: steps its range [b, e) from a scene built at frame b
/// and sends rank 0 the frame it reached, the error that stopped it ("" if none) and every
/// sub-step's result; then waits for rank 0 to have written everything.
int run_range(const RunInput& input, const RunSettings& st, Cluster& ranks, std::size_t b, std::size_t e) {
  WireWriter body;
  std::string error;
  std::size_t reached = b;  // frames read, as `next` counts them in run_frames
  const int K = st.substeps;
  if (b < e) {
    try {
      std::vector<Positions> first;
      if (b == 0)
        for (const TriMesh& m : input.meshes) first.push_back(detail::backed_copy(m.vertices));
      else
        first = input.frame(b);
      reached = b + 1;
      std::vector<TriMesh> meshes = backed_copy(input.meshes);
      for (std::size_t m = 0; m < meshes.size(); ++m) meshes[m].vertices = first[m];
      tbb::task_arena arena(st.threads);
      SceneOptions so = st.scene;
      so.arena = &arena;
      Scene scene(meshes, so);
      std::size_t next = b + 1;
      const FrameSource source = [&](std::vector<Positions>& frame) {
        if (next > e) return false;
        try {
          frame = input.frame(next);
        } catch (const std::exception& ex) {
          error = ex.what();
          return false;
        }
        reached = ++next;
        return true;
      };
      const StepSink sink = [&](const PipelineStep& ps) {
        body.put<std::uint64_t>(b * std::size_t(K) + ps.index);
        body.put(ps.result.earliest_toi);
        body.put(ps.result.stats);
        body.put<std::uint64_t>(ps.result.contacts.size());
        body.bytes.append(reinterpret_cast<const char*>(ps.result.contacts.data()),
                          ps.result.contacts.size() * sizeof(Contact));
      };
      PipelineOptions po;
      po.substeps = K;
      po.method = st.scene.method;
      arena.execute([&] { run_frame_pipeline(scene, std::move(first), source, sink, po); });
    } catch (const std::exception& ex) {
      if (error.empty()) error = ex.what();
    }
  }
  WireWriter head;
  head.put<std::uint64_t>(reached);
  head.put_text(error);
  ranks.send(0, kRangeTag, head.bytes + body.bytes);
  (void)ranks.recv(0, kDoneTag);
  return kExitClean;
}

}  // namespace

namespace {

int run_frames_here(const RunInput& input, const RunSettings& st, const std::string& command, RunReport* report,
                    Cluster* ranks, bool& gathered);

}  // namespace

int run_frames(const RunInput& input, const RunSettings& st, const std::string& command, RunReport* report,
               Cluster* ranks) {
  if (!ranks || ranks->size() == 1) {
    bool gathered = true;
    return run_frames_here(input, st, command, report, nullptr, gathered);
  }
  // until rank 0 starts waiting for the others, an error is every rank's own (the same input
  // and options on each): it ends each rank as in one process
  bool gathered = true;
  try {
    return run_frames_here(input, st, command, report, ranks, gathered);
  } catch (const std::exception& e) {
    if (gathered) throw;
    // the other ranks are waiting for rank 0 (or rank 0 for them): stop them all
    std::fflush(stdout);
    std::fprintf(stderr, "%s: %s: %s; stopping every rank\n", command.c_str(), ranks->where().c_str(), e.what());
    ranks->abort(2);
    throw;
  }
}

namespace {

int run_frames_here(const RunInput& input, const RunSettings& st, const std::string& command, RunReport* report,
                    Cluster* ranks, bool& gathered) {
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
  if (!st.image.empty()) (void)image_format("--image", st.image);
  if (!st.colored.empty()) check_extension("--colored", st.colored, {".ply"});
  std::vector<Positions> first;
  for (const TriMesh& m : input.meshes) first.push_back(detail::backed_copy(m.vertices));
  check_min_distance(st.scene.min_distance, first);
  const int R = ranks ? ranks->size() : 1;
  if (R > 1 && ranks->rank() != 0) {
    const int r = ranks->rank();
    return run_range(input, st, *ranks, range_begin(steps, r, R), range_begin(steps, r + 1, R));
  }
  // rank 0 steps frames 0 to `last` (all of them in one process); from here on the other
  // ranks wait for it, and it for them
  if (R > 1) gathered = false;
  const std::size_t last = R > 1 ? range_begin(steps, 1, R) : steps;

  tbb::task_arena arena(st.threads);
  SceneOptions so = st.scene;
  so.arena = &arena;
  // Frame 1 is read while the scene is built (its parallel set-up has the other threads); an
  // error reading it is reported where the pipeline would have met it.
  std::optional<std::vector<Positions>> frame1;
  std::string frame1_error;
  tbb::task_group prefetch;
  if (last >= 1)
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
  Scene scene(backed_copy(input.meshes), so);  // validates the meshes and the options before any file exists
  arena.execute([&] { prefetch.wait(); });
  std::size_t nv = 0, nf = 0;
  for (const TriMesh& m : input.meshes) nv += m.num_vertices(), nf += m.num_faces();
  if (report) report->frames = input.frames, report->triangles = nf;
  if (!st.silent) {
  std::printf("%s: %zu frames, %s vertices, %s triangles%s; method %s, %d thread%s", input.description.c_str(),
              input.frames, grouped(nv).c_str(), grouped(nf).c_str(),
              input.meshes.size() > 1 ? (" in " + std::to_string(input.meshes.size()) + " meshes").c_str() : "",
              to_string(st.scene.method), st.threads, st.threads == 1 ? "" : "s");
  if (K > 1) std::printf(", %d sub-steps per step", K);
  if (R > 1) std::printf("; %d ranks, each stepping its own range of frames", R);
  std::printf("\n");
  }

  const RunFacts facts{input.description, input.frames, K, to_string(st.scene.method), st.scene.min_distance};
  Outputs out;
  if (!st.contacts.empty()) out.contacts = std::make_unique<ContactsFile>(st.contacts, facts, input.meshes);
  if (!st.stats.empty()) out.stats = std::make_unique<StatsFile>(st.stats, facts);

  ProgressBar bar(!st.quiet && ProgressBar::stderr_is_terminal(), steps);
  const RunTable table(st.verbose);
  const FrameNames names = input.frame_files.empty() ? FrameNames() : FrameNames(input.frame_files);
  if (!st.quiet) {
    table.print_legend(names, input.frames);
    table.print_header();
  }
  StepAccumulator acc(K);
  RunTotals totals;
  SnapshotPicker picker(st.image_step, K);
  const bool pictures = wants_pictures(st);
  std::size_t steps_done = 0;

  const InterruptCleanup on_signal([&](int sig) {
    bar.erase();
    std::fflush(stdout);
    std::fprintf(stderr, "%s: interrupted by %s after %zu of %zu steps\n", command.c_str(), signal_name(sig),
                 steps_done, steps);
    out.stop(st.partial,
             std::string("interrupted by ") + signal_name(sig) + " after " + std::to_string(steps_done) + " of " +
                 std::to_string(steps) + " steps",
             steps_done, command, st.mute);
  });

  // A frame that cannot be read ends the sequence there, so that every step before it is
  // still stepped and written; the error is raised once they are.
  std::size_t next = 1;
  std::string source_error;
  const FrameSource source = [&](std::vector<Positions>& frame) {
    if (next > last) return false;
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
    if (pictures) picker.offer(k, j, ps.result);  // a copy of the contacts: only for a picture
    if (acc.add(k, j, ps.result)) {
      totals.add(acc.row());
      steps_done = k + 1;
      if (!st.quiet) bar.print_above([&] { table.print_row(acc.row()); });
      if (st.on_step) st.on_step(acc.row());
    }
    bar.update(double(k) + double(j + 1) / K, totals.vf + totals.ee);
  };
  PipelineOptions po;
  po.substeps = K;
  po.method = st.scene.method;
  try {
    arena.execute([&] { run_frame_pipeline(scene, first, source, sink, po); });
    if (R > 1) {
      // the other ranks' ranges, in frame order: replayed through the same sink; after a range
      // that stopped early, the later ones are received and dropped
      for (int r = 1; r < R; ++r) {
        const std::string bytes = ranks->recv(r, kRangeTag);
        if (!source_error.empty()) continue;
        WireReader in{bytes};
        const auto reached = in.get<std::uint64_t>();
        const std::string error = in.get_text();
        while (!in.done()) {
          PipelineStep ps;
          ps.index = in.get<std::uint64_t>();
          ps.result.earliest_toi = in.get<double>();
          ps.result.stats = in.get<StepStats>();
          ps.result.contacts.resize(in.get<std::uint64_t>());
          for (Contact& c : ps.result.contacts) c = in.get<Contact>();
          sink(ps);
        }
        if (!error.empty()) {
          source_error = error;
          next = reached;
          std::fprintf(stderr, "%s: rank %d of %d: %s\n", command.c_str(), r, R, error.c_str());
        }
      }
      for (int r = 1; r < R; ++r) ranks->send(r, kDoneTag, std::string());
      gathered = true;
    }
  } catch (const std::exception& e) {
    {
      std::lock_guard<std::mutex> lock(interrupt_mutex());
      bar.erase();
      std::fflush(stdout);
      out.stop(st.partial, e.what(), steps_done, command, st.mute);
    }
    // the steps are handed over in order: the one after the last finished is where it failed
    const RunStop stop{steps, steps_done, e.what()};
    if (report) report->totals = totals, report->wall_seconds = seconds_since(wall_start);
    if (!st.silent) print_summary(totals, names, to_string(st.scene.method), st.threads, seconds_since(wall_start), &stop);
    std::fflush(stdout);
    throw;
  }
  bar.erase();
  const double wall = seconds_since(wall_start);
  if (report) report->totals = totals, report->wall_seconds = wall;
  if (!source_error.empty()) {
    {
      std::lock_guard<std::mutex> lock(interrupt_mutex());
      std::fflush(stdout);
      out.stop(st.partial, source_error, steps_done, command, st.mute);
    }
    // frame `next` could not be read: every step before the one ending there has finished
    const RunStop stop{steps, next - 1, source_error};
    if (!st.silent) print_summary(totals, names, to_string(st.scene.method), st.threads, wall, &stop);
    std::fflush(stdout);
    throw Error(source_error);
  }
  {
    std::lock_guard<std::mutex> lock(interrupt_mutex());
    for (StreamedFile* f : out.files()) f->finish(steps, summary_json(totals, wall));
  }
  if (!st.silent) print_summary(totals, names, to_string(st.scene.method), st.threads, wall);
  write_pictures(input, st, names, picker.chosen());
  return totals.vf + totals.ee > 0 && !st.exit_zero ? kExitFound : kExitClean;
}

}  // namespace

}  // namespace mccd::cli
