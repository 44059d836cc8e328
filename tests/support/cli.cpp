#include "support/cli.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include <mccd/geometry/mesh_io.h>

#include "support/data.h"

extern char** environ;

namespace mccd::test {

namespace fs = std::filesystem;

ScratchDir::ScratchDir(const std::string& tag) {
  static std::atomic<int> counter{0};
  std::random_device rd;
  path_ = fs::temp_directory_path() /
          (tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + "_" + std::to_string(rd()));
  fs::create_directories(path_);
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

std::vector<std::string> ScratchDir::names() const {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(path_)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

CliProcess::CliProcess(const std::vector<std::string>& args, const fs::path& capture_dir, const fs::path& cwd) {
  static std::atomic<int> counter{0};
  const std::string tag = std::to_string(counter++);
  out_ = capture_dir / ("stdout" + tag + ".txt");
  err_ = capture_dir / ("stderr" + tag + ".txt");
  std::vector<std::string> argv_s{cli_path()};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (!cwd.empty()) posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
  const int rc = posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot start " + cli_path());
}

CliProcess::~CliProcess() {
  if (!waited_ && pid_ > 0) {
    ::kill(pid_, SIGKILL);
    int st = 0;
    ::waitpid(pid_, &st, 0);
  }
}

void CliProcess::signal(int sig) const { ::kill(pid_, sig); }

std::string CliProcess::out_so_far() const { return slurp(out_); }

CliResult CliProcess::wait() {
  int st = 0;
  ::waitpid(pid_, &st, 0);
  waited_ = true;
  CliResult r;
  if (WIFEXITED(st)) r.status = WEXITSTATUS(st);
  if (WIFSIGNALED(st)) r.signal = WTERMSIG(st);
  r.out = slurp(out_);
  r.err = slurp(err_);
  return r;
}

CliResult run_cli(const std::vector<std::string>& args, const fs::path& cwd) {
  const ScratchDir capture("mccd_cli_capture");
  CliProcess p(args, capture.path(), cwd);
  return p.wait();
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) out.push_back(line);
  return out;
}

std::string write_frames(const fs::path& dir, const std::string& name, const TriMesh& mesh,
                         const std::vector<Positions>& frames) {
  for (std::size_t f = 0; f < frames.size(); ++f) {
    TriMesh m = mesh;
    m.vertices = frames[f];
    char file[64];
    std::snprintf(file, sizeof file, "%s%03zu.ply", name.c_str(), f);
    write_ply((dir / file).string(), m);
  }
  return (dir / (name + "%03d.ply")).string();
}

}  // namespace mccd::test
