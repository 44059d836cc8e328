// Runs the built `mccd info` and checks its output and exit status.
#include <gtest/gtest.h>

#include <mccd/geometry/topology.h>
#include "fixtures/shapes.h"
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <mccd/geometry/mesh.h>
#include <mccd/geometry/mesh_io.h>
#include "support/data.h"

namespace fs = std::filesystem;

namespace {

class CliTempDir {
 public:
  CliTempDir() {
    static std::atomic<int> counter{0};
    std::random_device rd;
    path_ = fs::temp_directory_path() / ("mccd_cli_info_" + std::to_string(::getpid()) + "_" +
                                         std::to_string(counter++) + "_" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~CliTempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

struct RunResult {
  int status = -1;
  std::string out, err;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// Runs `mccd info ARGS`, capturing stdout (pipe) and stderr (a file).
RunResult run_info(const std::string& args) {
  CliTempDir tmp;
  const std::string err_file = tmp.file("stderr.txt");
  std::string cmd(1, '\'');
  cmd += mccd::test::cli_path();
  cmd += "' info ";
  cmd += args;
  cmd += " 2>'";
  cmd += err_file;
  cmd += '\'';
  RunResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) {
    ADD_FAILURE() << "popen failed: " << cmd;
    return r;
  }
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) r.out.append(buf, n);
  const int status = ::pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = slurp(err_file);
  return r;
}

std::string q(const std::string& s) {
  std::string out(1, '\'');
  out += s;
  out += '\'';
  return out;
}

/// The value printed after `label:` (up to the end of the line), trimmed.
std::string field(const std::string& out, const std::string& label, std::size_t from = 0) {
  const std::size_t at = out.find("  " + label + ":", from);
  if (at == std::string::npos) return "(missing " + label + ")";
  std::size_t b = at + label.size() + 3;
  while (b < out.size() && out[b] == ' ') ++b;
  return out.substr(b, out.find('\n', b) - b);
}

}  // namespace

TEST(CliInfo, RealClothBall) {
  const fs::path path = mccd::test::data_dir() / "toi/cloth-ball/frames/cloth_ball92.ply";
  MCCD_REQUIRE_DATA(path);
  const RunResult r = run_info(q(path.string()));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')), path.string());
  EXPECT_EQ(field(r.out, "vertices"), "46598");
  EXPECT_EQ(field(r.out, "triangles"), "92230");
  EXPECT_EQ(field(r.out, "edges"), "138825");
  EXPECT_EQ(field(r.out, "non-manifold edges"), "0");
  EXPECT_EQ(field(r.out, "zero-area triangles"), "0");
  EXPECT_NE(field(r.out, "boundary edges").find_first_of("0123456789"), std::string::npos);
  EXPECT_EQ(field(r.out, "bounding box").rfind("[", 0), 0u);
}

TEST(CliInfo, GeneratedMeshes) {
  CliTempDir tmp;
  const std::string grid = tmp.file("grid.ply"), sphere = tmp.file("sphere.obj");
  mccd::write_ply(grid, mccd::make_grid_mesh(3, 2.0));
  mccd::write_obj(sphere, mccd::make_sphere_mesh(6, 8));
  const RunResult r = run_info(q(grid) + " " + q(sphere));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(field(r.out, "vertices"), "16");
  EXPECT_EQ(field(r.out, "triangles"), "18");
  EXPECT_EQ(field(r.out, "edges"), "33");
  EXPECT_EQ(field(r.out, "boundary edges"), "12");
  EXPECT_EQ(field(r.out, "bounding box"), "[-1, -1, 0] .. [1, 1, 0]");
  const std::size_t second = r.out.find(sphere + "\n");
  ASSERT_NE(second, std::string::npos) << r.out;
  EXPECT_EQ(field(r.out, "vertices", second), "42");
  EXPECT_EQ(field(r.out, "triangles", second), "80");
  EXPECT_EQ(field(r.out, "boundary edges", second), "0");
}

TEST(CliInfo, ZeroAreaAndNonManifoldCounted) {
  CliTempDir tmp;
  const std::string p = tmp.file("odd.obj");
  std::ofstream(p) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 2 0 0\n"
                      "f 1 2 3\nf 2 1 4\nf 1 2 5\nf 1 2 6\n";  // (1,2,6) is collinear
  const RunResult r = run_info(q(p));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(field(r.out, "non-manifold edges"), "1");
  EXPECT_EQ(field(r.out, "zero-area triangles"), "1");
}

TEST(CliInfo, MalformedFile) {
  CliTempDir tmp;
  const std::string p = tmp.file("bad.ply");
  std::ofstream(p) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nend_header\n0 0 0\n1 abc 0\n0 1 0\n";
  const RunResult r = run_info(q(p));
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out.find("vertices"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find(p + ": line 9: expected a number for property 'y' of vertex 1, got 'abc'"), std::string::npos)
      << r.err;
}

TEST(CliInfo, MissingFileAmongGoodOnes) {
  CliTempDir tmp;
  const std::string good = tmp.file("good.ply"), missing = tmp.file("missing.ply");
  mccd::write_ply(good, mccd::make_grid_mesh(2));
  const RunResult r = run_info(q(missing) + " " + q(good));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(missing + ": cannot open"), std::string::npos) << r.err;
  EXPECT_EQ(field(r.out, "vertices"), "9");  // the good file is still reported
}

TEST(CliInfo, UsageErrors) {
  RunResult r = run_info("");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("mccd info: error: FILE is required"), std::string::npos) << r.err;
  r = run_info("--bogus x.ply");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown option --bogus"), std::string::npos) << r.err;
}
