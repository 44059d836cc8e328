#pragma once
/// @file The engine of `mccd run` and `mccd demo`: a sequence of frames stepped through the
/// frame pipeline, with the table, the progress bar, the streamed output files, the exit
/// status, and the picture of the first contact.
///
/// Order of work: the scene is built and every option checked before any file is opened; the
/// frames are then read ahead, stepped and written in frame order (parallel/frame_pipeline.h);
/// each finished sub-step goes to the files and each finished step to the table. A frame that
/// cannot be read ends the sequence there: every step before it is kept (the files marked
/// incomplete, or removed, as --partial says) and the run exits with status 2. SIGINT and
/// SIGTERM do the same from the interrupt watcher (interrupt.h). The picture is drawn after
/// the last step, from the two frames around the chosen step, read again.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <mccd/core/options.h>
#include <mccd/geometry/mesh.h>

#include "run_files.h"
#include "run_table.h"

namespace mccd::cli {

/// What is run: meshes (triangles, and the positions of frame 0) and a way to get frame i.
struct RunInput {
  std::string description;  ///< "cloth_ball92.ply .. cloth_ball93.ply", "built-in scene cloth"
  /// The file of each frame when they come from files (the summary names steps by them);
  /// empty: frames are named by number.
  std::vector<std::string> frame_files;
  std::vector<TriMesh> meshes;
  std::size_t frames = 0;   ///< at least 2
  /// The positions of frame i (one array per mesh), 0 <= i < frames. May throw mccd::Error
  /// naming the file and the frame.
  std::function<std::vector<Positions>(std::size_t i)> frame;
};

/// How it is run and what it writes (the options of `mccd run`).
struct RunSettings {
  SceneOptions scene;  ///< method, volume, rebuild ratios, minimum distance (the arena is set here)
  int substeps = 1;
  int threads = 1;
  bool quiet = false, verbose = false, exit_zero = false;
  std::string contacts, stats;  ///< output files ("" for none)
  Partial partial = Partial::Keep;
  std::string image, colored;   ///< picture and coloured mesh ("" for none)
  std::optional<std::size_t> image_step;
  int image_width = 1200, image_height = 900;
  std::string camera;           ///< "EX,EY,EZ[,TX,TY,TZ[,UX,UY,UZ]]" or "" for automatic
  std::optional<Vec3> up;       ///< the scene's up direction when known (else guessed, see up_axis())
  bool silent = false;          ///< print nothing on stdout (`mccd batch` prints its own lines)
  /// Print nothing at all, on stdout or stderr (no picture lines, no word of the files kept or
  /// removed when a run stops early): with silent and quiet, for callers that report through
  /// on_step and exceptions (the Python module).
  bool mute = false;
  /// Called with each finished step's row, in step order, one call at a time (from whichever
  /// thread finished the step). It may throw to stop the run: the files of the finished steps
  /// are then kept or removed as `partial` says and the exception is rethrown.
  std::function<void(const StepRow&)> on_step;
};

/// What a run found, for `mccd batch`'s summary (filled as far as the run got, also when it
/// throws).
struct RunReport {
  std::size_t frames = 0, triangles = 0;
  RunTotals totals;
  double wall_seconds = 0;
};

class Cluster;

/// Runs `input` with `settings`; prints the table (unless quiet) and the summary. Returns the
/// exit status: 0 no contact, 1 contacts found (0 with exit_zero). Throws mccd::Error (status
/// 2) for refused input, after keeping or removing the files of the finished steps; when it
/// stops after the first step began, the summary printed first says where and why.
/// `command` names the command in messages ("mccd run"). `report`, if given, receives the
/// totals.
///
/// With `ranks` of more than one process (mpirun, srun), the frame intervals are split among
/// them in contiguous ranges of (nearly) equal numbers of steps: each rank builds its own scene
/// at its range's first frame, on its own arena of `settings.threads` threads, and sends its
/// steps' results to rank 0, which alone prints and writes them, in frame order, as one process
/// would (a step's contacts depend only on its two frames; the statistics of the front and of
/// the hierarchy at each range's first step differ, and the times). Ranks other than 0 print
/// nothing and return 0; rank 0 returns the run's status or throws.
int run_frames(const RunInput& input, const RunSettings& settings, const std::string& command,
               RunReport* report = nullptr, Cluster* ranks = nullptr);

}  // namespace mccd::cli
