// Runs the built `mccd run`, `mccd demo` and `mccd toi-check` end to end.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <mccd/core/scene.h>
#include "fixtures/scenes.h"
#include <mccd/geometry/mesh_io.h>
#include "support/data.h"

namespace fs = std::filesystem;

namespace {
struct Out {
  int status;
  std::string text;  // stdout and stderr
};

Out run_cli(const std::string& args) {
  const std::string cmd = mccd::test::cli_path() + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  Out o{-1, ""};
  if (!p) return o;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) o.text.append(buf, n);
  const int st = pclose(p);
  o.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return o;
}

std::string scratch(const std::string& name) {
  return (fs::temp_directory_path() / ("mccd_cli_run_" + std::to_string(::getpid()) + "_" + name)).string();
}
}  // namespace

TEST(CliToiCheck, ClothFunnelEveryMethodMissesNothing) {
  const fs::path dir = mccd::test::data_dir() / "toi/cloth-funnel";
  MCCD_REQUIRE_DATA(dir);
  for (const char* m : {"bruteforce", "traverse", "front"}) {
    Out o = run_cli("toi-check " + dir.string() + " --method " + m);
    EXPECT_EQ(o.status, 0) << o.text;
    EXPECT_NE(o.text.find("vertex-face: 92 listed pairs, 27 true; reported 27: found 27, missed 0"), std::string::npos) << o.text;
    EXPECT_NE(o.text.find("edge-edge  : 263 listed pairs, 107 true"), std::string::npos) << o.text;
    EXPECT_NE(o.text.find("OK: 0 true pairs missed"), std::string::npos) << o.text;
  }
}

TEST(CliToiCheck, ClothBallFrontMissesNothing) {
  const fs::path dir = mccd::test::data_dir() / "toi/cloth-ball";
  MCCD_REQUIRE_DATA(dir);
  Out o = run_cli("toi-check " + dir.string() + " --method front");
  EXPECT_EQ(o.status, 0) << o.text;
  EXPECT_NE(o.text.find("found 19032, missed 0"), std::string::npos) << o.text;
  EXPECT_NE(o.text.find("found 94822, missed 0"), std::string::npos) << o.text;
}

TEST(CliToiCheck, RefusesMissingFolder) {
  Out o = run_cli("toi-check /nonexistent/scene");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.text.find("/nonexistent/scene"), std::string::npos) << o.text;
}

TEST(CliRun, BuiltInSceneWritesContactsCsv) {
  const std::string csv = scratch("contacts.csv");
  Out o = run_cli("run --scene cloth --size 1 --frames 11 --method front --contacts " + csv);
  ASSERT_EQ(o.status, 0) << o.text;
  EXPECT_NE(o.text.find("total over 10 steps (fbd)"), std::string::npos) << o.text;
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "step,kind,mesh_a,a,mesh_b,b,a_v0,a_v1,b_v0,b_v1,toi");
  std::size_t rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_GT(rows, 0u);
  EXPECT_FALSE(fs::exists(csv + ".tmp"));
  fs::remove(csv);
}

TEST(CliRun, MethodsPrintTheSameContactTotals) {
  std::string totals[3];
  int i = 0;
  for (const char* m : {"bruteforce", "traverse", "front"}) {
    Out o = run_cli(std::string("run --scene spheres --size 1 --frames 9 --substeps 2 --quiet --method ") + m);
    ASSERT_EQ(o.status, 0) << o.text;
    const auto at = o.text.find("contacts ");
    ASSERT_NE(at, std::string::npos);
    totals[i++] = o.text.substr(at, o.text.find(',', at) - at);
  }
  EXPECT_EQ(totals[0], totals[1]);
  EXPECT_EQ(totals[0], totals[2]);
}

TEST(CliRun, BadInputLeavesNoContactsFile) {
  const std::string csv = scratch("never.csv");
  Out o = run_cli("run /nonexistent/frame%03d.ply --contacts " + csv);
  EXPECT_EQ(o.status, 2) << o.text;
  EXPECT_FALSE(fs::exists(csv));
  o = run_cli("run --scene cloth --method sideways");
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.text.find("unknown method 'sideways'"), std::string::npos) << o.text;
  o = run_cli("run --scene cloth --substeps 0");
  EXPECT_EQ(o.status, 2);
}

TEST(CliDemo, RunsAndAgrees) {
  Out o = run_cli("demo --size 2 --frames 11");
  EXPECT_EQ(o.status, 0) << o.text;
  EXPECT_NE(o.text.find("fewer"), std::string::npos) << o.text;
}

TEST(CliRun, FrameFilesThroughThePipeline) {
  const fs::path dir = fs::temp_directory_path() / ("mccd_cli_frames_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  // 6 frames of a folding cloth as PLY files; frame 4 of a second set has other triangles
  mccd::AnimatedScene s = mccd::make_folding_cloth(12, 6);
  for (std::size_t f = 0; f < s.frames.size(); ++f) {
    mccd::TriMesh m = s.meshes[0];
    m.vertices = s.frames[f][0];
    char name[32];
    std::snprintf(name, sizeof name, "frame%03zu.ply", f);
    mccd::write_ply((dir / name).string(), m);
    if (f == 4) std::swap(m.faces[7][0], m.faces[7][1]);
    std::snprintf(name, sizeof name, "bad%03zu.ply", f);
    mccd::write_ply((dir / name).string(), m);
  }
  Out files = run_cli("run " + (dir / "frame%03d.ply").string() + " --quiet --method front");
  ASSERT_EQ(files.status, 0) << files.text;
  EXPECT_NE(files.text.find("6 frames of"), std::string::npos) << files.text;
  EXPECT_NE(files.text.find("total over 5 steps (fbd)"), std::string::npos) << files.text;
  // the same frames in memory give the same totals
  mccd::Scene scene(s.meshes);
  std::size_t contacts = 0;
  for (std::size_t f = 1; f < s.frames.size(); ++f)
    contacts += scene.advance(std::vector<mccd::PositionsView>(s.frames[f].begin(), s.frames[f].end())).contacts.size();
  EXPECT_NE(files.text.find("contacts " + std::to_string(contacts) + ","), std::string::npos) << files.text;

  const std::string csv = (dir / "out.csv").string();
  Out bad = run_cli("run " + (dir / "bad%03d.ply").string() + " --quiet --contacts " + csv);
  EXPECT_EQ(bad.status, 2) << bad.text;
  EXPECT_NE(bad.text.find("bad004.ply (frame 4): face 7"), std::string::npos) << bad.text;
  EXPECT_FALSE(fs::exists(csv));
  EXPECT_FALSE(fs::exists(csv + ".tmp"));
  fs::remove_all(dir);
}
