#pragma once
/// @file Running the built `mccd` tool from tests: arguments passed as a vector (no shell),
/// stdout and stderr captured apart, the exit status or the terminating signal, a working
/// folder, and a scratch folder removed at the end.
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

#include <mccd/geometry/mesh.h>

namespace mccd::test {

/// A fresh empty folder under the system temporary folder, removed with its contents.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag = "mccd_cli");
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  /// Names of the files in the folder, sorted (hidden ones included).
  std::vector<std::string> names() const;

 private:
  std::filesystem::path path_;
};

struct CliResult {
  int status = -1;      ///< exit status, or -1 when killed by a signal
  int signal = 0;       ///< the terminating signal, or 0
  std::string out, err; ///< stdout and stderr
};

/// A started `mccd` process whose output goes to files in `dir`.
class CliProcess {
 public:
  /// Starts `mccd ARGS...` in `cwd` (empty: the test's own folder).
  CliProcess(const std::vector<std::string>& args, const std::filesystem::path& capture_dir,
             const std::filesystem::path& cwd = {});
  ~CliProcess();
  pid_t pid() const { return pid_; }
  /// Sends `sig` to the process.
  void signal(int sig) const;
  /// Waits for the end and collects the output.
  CliResult wait();
  /// What it has written to stdout so far.
  std::string out_so_far() const;

 private:
  pid_t pid_ = -1;
  std::filesystem::path out_, err_;
  bool waited_ = false;
};

/// Runs `mccd ARGS...` to the end.
CliResult run_cli(const std::vector<std::string>& args, const std::filesystem::path& cwd = {});

/// The whole content of a file ("" when missing).
std::string slurp(const std::filesystem::path& path);
/// The lines of `text` (without their '\n').
std::vector<std::string> lines_of(const std::string& text);

/// Writes frames `frames[i]` of `mesh`'s triangles as `dir/NAME%03d.ply` and returns the
/// printf pattern.
std::string write_frames(const std::filesystem::path& dir, const std::string& name, const TriMesh& mesh,
                         const std::vector<Positions>& frames);

}  // namespace mccd::test
