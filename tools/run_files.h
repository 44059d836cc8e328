#pragma once
/// @file The files `mccd run` writes as steps finish: the contacts (`--contacts FILE.csv` or
/// `FILE.json`) and the per-step statistics (`--stats FILE.json`).
///
/// Each is written through an AtomicFile: streamed into a temporary beside the target
/// (flushed after every step, so a long run can be followed), renamed to the final name at the
/// end. When a run stops early (an input error, SIGINT, SIGTERM), `stop()` either keeps the
/// finished steps under the final name, marked incomplete (CSV: a last line
/// "# incomplete: REASON"; JSON: "complete": false and "stopped": REASON), or removes the
/// temporary and writes nothing. Never a stray temporary.
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include <mccd/core/contact.h>
#include <mccd/geometry/atomic_file.h>
#include <mccd/geometry/mesh.h>

namespace mccd::cli {

/// What a run does with its files when it stops early.
enum class Partial { Keep, Remove };

/// Facts about the run, written at the head of the JSON files.
struct RunFacts {
  std::string input;       ///< what was run (files or scene)
  std::size_t frames = 0;  ///< frames in the sequence
  int substeps = 1;        ///< linear sub-steps per frame interval
  std::string method;
  double min_distance = 0;
};

/// The frame time of a local time `t` in [0, 1] of sub-step `substep` (of `substeps`) of the
/// step from frame `step` to `step` + 1: step + (substep + t) / substeps.
double frame_time(std::size_t step, std::size_t substep, int substeps, double t);

/// One streamed output file; the formats below fill in the records and the ends.
class StreamedFile {
 public:
  virtual ~StreamedFile() = default;
  /// Closes the records and renames the file to its final name.
  void finish(std::size_t steps, const nlohmann::json& extra);
  /// After an error or a signal: Partial::Keep closes the records marked incomplete with
  /// `why` and renames the file to its final name; Partial::Remove removes the temporary.
  /// Safe to call more than once, and after finish() (then it does nothing).
  void stop(Partial partial, const std::string& why, std::size_t steps) noexcept;
  const std::string& path() const { return file_.path(); }
  bool done() const { return done_; }

 protected:
  explicit StreamedFile(const std::string& path) : file_(path) {}
  /// The last bytes: `why` empty when complete.
  virtual std::string ending(std::size_t steps, const std::string& why, const nlohmann::json& extra) const = 0;
  AtomicFile file_;
  bool done_ = false;
};

/// `--contacts FILE`: one record per contact and sub-step (frame, substep, kind, mesh and
/// feature ids, the four vertex ids of the elementary test, time of impact in frame time).
class ContactsFile : public StreamedFile {
 public:
  /// `.csv` or `.json` by extension (anything else is refused with mccd::Error). `meshes` give
  /// the face vertex ids of vertex-face contacts and must outlive the file.
  ContactsFile(const std::string& path, const RunFacts& facts, const std::vector<TriMesh>& meshes);
  /// Appends one sub-step's contacts and flushes.
  void add(std::size_t step, std::size_t substep, const StepResult& r);

 private:
  std::string ending(std::size_t steps, const std::string& why, const nlohmann::json& extra) const override;
  const std::vector<TriMesh>& meshes_;
  int substeps_;
  bool json_, first_ = true;
};

/// `--stats FILE.json`: one record per sub-step with every counter and stage time of
/// StepStats, and a summary at the end.
class StatsFile : public StreamedFile {
 public:
  StatsFile(const std::string& path, const RunFacts& facts);
  void add(std::size_t step, std::size_t substep, const StepResult& r);

 private:
  std::string ending(std::size_t steps, const std::string& why, const nlohmann::json& extra) const override;
  int substeps_;
  bool first_ = true;
};

/// Refuses an output path whose extension is not one of `extensions` (".csv", ".json").
void check_extension(const std::string& option, const std::string& path, const std::vector<std::string>& extensions);

}  // namespace mccd::cli
