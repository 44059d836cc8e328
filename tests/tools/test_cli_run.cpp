// Runs the built `mccd run` end to end on small generated sequences: the table and summary,
// the contacts and statistics files against the library, the exit statuses, a run failing at
// its last frame, and SIGINT / SIGTERM (nothing temporary left behind).
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/mesh_io.h>

#include "fixtures/scenes.h"
#include "support/cli.h"
#include "support/data.h"

namespace fs = std::filesystem;
using namespace mccd::test;

namespace {

/// The CSV rows `mccd run --contacts X.csv` should write for `scene` with `substeps` linear
/// sub-steps, from the library itself (the frame pipeline's interpolation).
std::vector<std::string> library_rows(const mccd::AnimatedScene& s, int substeps, std::size_t steps) {
  mccd::Scene scene(s.meshes);
  std::vector<std::string> rows;
  std::vector<mccd::Positions> prev = s.frames[0];
  for (std::size_t k = 0; k < steps; ++k) {
    const std::vector<mccd::Positions>& next = s.frames[k + 1];
    for (int j = 0; j < substeps; ++j) {
      std::vector<mccd::Positions> end = next;
      const double u = double(j + 1) / substeps;
      if (j + 1 < substeps)
        for (std::size_t m = 0; m < end.size(); ++m) end[m].mat() = (1 - u) * s.frames[k][m].mat() + u * next[m].mat();
      const mccd::StepResult r = scene.step(std::vector<mccd::PositionsView>(prev.begin(), prev.end()),
                                            std::vector<mccd::PositionsView>(end.begin(), end.end()));
      for (const mccd::Contact& c : r.contacts) {
        const bool vf = c.kind == mccd::ContactKind::VertexFace;
        std::array<std::uint32_t, 4> v{};
        if (vf) {
          const auto& f = s.meshes[c.mesh_b].faces[c.b];
          v = {c.a, f[0], f[1], f[2]};
        } else {
          v = {c.a_vertices[0], c.a_vertices[1], c.b_vertices[0], c.b_vertices[1]};
        }
        char buf[256];
        std::snprintf(buf, sizeof buf, "%zu,%d,%s,%u,%u,%u,%u,%u,%u,%u,%u,%.17g,%.17g", k, j, vf ? "vf" : "ee",
                      c.mesh_a, c.a, c.mesh_b, c.b, v[0], v[1], v[2], v[3],
                      double(k) + (double(j) + c.toi) / substeps, c.toi);
        rows.push_back(buf);
      }
      prev = end;
    }
  }
  return rows;
}

/// A folding cloth written as frame files (self-contact from the second step on).
struct ClothFiles {
  ScratchDir dir{"mccd_cli_run"};
  mccd::AnimatedScene scene = mccd::make_folding_cloth(12, 6);
  std::string pattern = write_frames(dir.path(), "frame", scene.meshes[0], frames());
  std::vector<mccd::Positions> frames() const {
    std::vector<mccd::Positions> out;
    for (const auto& f : scene.frames) out.push_back(f[0]);
    return out;
  }
};

/// The table rows (lines that start with a right-aligned step number).
std::vector<std::string> table_rows(const std::string& out) {
  std::vector<std::string> rows;
  for (const std::string& l : lines_of(out))
    if (l.size() > 6 && l.find_first_not_of(' ') < 6 && std::isdigit(static_cast<unsigned char>(l[5]))) rows.push_back(l);
  return rows;
}

}  // namespace

TEST(CliRun, TableSummaryAndContactsCsvMatchTheLibrary) {
  ClothFiles cloth;
  const std::string csv = cloth.dir.file("contacts.csv");
  const auto r = run_cli({"run", cloth.pattern, "--method", "front", "--contacts", csv});
  ASSERT_EQ(r.status, 1) << r.err;  // collisions found
  EXPECT_EQ(r.err, "");             // not a terminal: no progress bar
  const std::vector<std::string> lines = lines_of(r.out);
  ASSERT_GE(lines.size(), 2u);
  EXPECT_NE(lines[0].find("6 frames, 169 vertices, 288 triangles; method fbd"), std::string::npos) << r.out;
  for (const char* column : {"step", "VF", "EE", "first impact", "time"})
    EXPECT_NE(lines[1].find(column), std::string::npos) << lines[1];
  EXPECT_EQ(table_rows(r.out).size(), 5u) << r.out;

  const std::vector<std::string> expected = library_rows(cloth.scene, 1, 5);
  ASSERT_FALSE(expected.empty());
  std::vector<std::string> rows = lines_of(slurp(csv));
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.front(), "frame,substep,kind,mesh_a,feature_a,mesh_b,feature_b,v0,v1,v2,v3,toi,t");
  rows.erase(rows.begin());
  EXPECT_EQ(rows, expected);
  EXPECT_NE(r.out.find("5 steps (frames 0 to 5)"), std::string::npos) << r.out;
  const std::string digits = std::to_string(expected.size());
  std::string count;  // grouped by thousands, as printed
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) count.push_back(',');
    count.push_back(digits[i]);
  }
  count.append(" contacts (");
  EXPECT_NE(r.out.find(count), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("first impact at frame time "), std::string::npos) << r.out;
  EXPECT_EQ(cloth.dir.names().size(), 7u);  // 6 frames and the CSV, nothing temporary
}

TEST(CliRun, SubstepsJsonContactsAndStatistics) {
  ClothFiles cloth;
  const std::string contacts = cloth.dir.file("c.json"), stats = cloth.dir.file("s.json");
  const auto r = run_cli({"run", cloth.pattern, "--substeps", "3", "--contacts", contacts, "--stats", stats});
  ASSERT_EQ(r.status, 1) << r.err;
  const nlohmann::json c = nlohmann::json::parse(slurp(contacts)), s = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(c["complete"], true);
  EXPECT_EQ(c["substeps"], 3);
  EXPECT_EQ(c["finished_steps"], 5);
  const std::vector<std::string> expected = library_rows(cloth.scene, 3, 5);
  ASSERT_EQ(c["contacts"].size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const auto& x = c["contacts"][i];
    const std::vector<std::uint32_t> v = x["vertices"];
    char buf[256];
    std::snprintf(buf, sizeof buf, "%zu,%d,%s,%u,%u,%u,%u,%u,%u,%u,%u,%.17g,%.17g", x["frame"].get<std::size_t>(),
                  x["substep"].get<int>(), x["kind"].get<std::string>().c_str(), x["mesh_a"].get<unsigned>(),
                  x["feature_a"].get<unsigned>(), x["mesh_b"].get<unsigned>(), x["feature_b"].get<unsigned>(), v[0],
                  v[1], v[2], v[3], x["toi"].get<double>(), x["t"].get<double>());
    ASSERT_EQ(buf, expected[i]) << i;
    // frame time: inside the step's frame interval
    EXPECT_GE(x["toi"].get<double>(), x["frame"].get<double>());
    EXPECT_LE(x["toi"].get<double>(), x["frame"].get<double>() + 1);
  }
  EXPECT_EQ(s["complete"], true);
  ASSERT_EQ(s["steps"].size(), 15u);  // one record per sub-step
  std::size_t total = 0;
  for (const auto& step : s["steps"]) {
    total += step["contacts"].get<std::size_t>();
    // each sub-step tests volumes or skips patches certified free of self-collision
    EXPECT_GT(step["volume_tests"].get<std::uint64_t>() + step["culled_nodes"].get<std::uint64_t>(), 0u);
    EXPECT_TRUE(step["seconds"]["total"].is_number());
  }
  EXPECT_EQ(total, expected.size());
  EXPECT_EQ(s["summary"]["steps"], 5);
}

TEST(CliRun, ExitStatuses) {
  ScratchDir dir("mccd_cli_status");
  // a cloth sliding sideways without deforming: no collision
  mccd::TriMesh grid = mccd::make_folding_cloth(6, 2).meshes[0];
  std::vector<mccd::Positions> frames(4, grid.vertices);
  for (std::size_t f = 0; f < frames.size(); ++f)
    for (std::size_t v = 0; v < frames[f].rows(); ++v) frames[f](v, 0) += 0.1 * double(f);
  const std::string calm = write_frames(dir.path(), "calm", grid, frames);
  auto r = run_cli({"run", calm});
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("no collision in 3 steps (frames 0 to 3)"), std::string::npos) << r.out;

  r = run_cli({"run", "--scene", "cloth", "--size", "1", "--frames", "6", "--quiet"});
  EXPECT_EQ(r.status, 1) << r.err;
  r = run_cli({"run", "--scene", "cloth", "--size", "1", "--frames", "6", "--quiet", "--exit-zero"});
  EXPECT_EQ(r.status, 0) << r.err;
  r = run_cli({"run", (dir.path() / "missing%03d.ply").string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
}

TEST(CliRun, AFolderOfFramesInNaturalOrder) {
  ScratchDir dir("mccd_cli_folder");
  const auto scene = mccd::make_folding_cloth(8, 3);
  const char* names[] = {"s1.ply", "s2.ply", "s10.ply"};  // "s10" sorts last, not between
  for (int f = 0; f < 3; ++f) {
    mccd::TriMesh m = scene.meshes[0];
    m.vertices = scene.frames[std::size_t(f)][0];
    mccd::write_ply(dir.file(names[f]), m);
  }
  const auto r = run_cli({"run", dir.path().string(), "--quiet"});
  EXPECT_LE(r.status, 1) << r.err;
  EXPECT_NE(r.out.find("s1.ply .. s10.ply: 3 frames"), std::string::npos) << r.out;
  ScratchDir empty("mccd_cli_folder_empty");
  const auto e = run_cli({"run", empty.path().string()});
  EXPECT_EQ(e.status, 2);
  EXPECT_NE(e.err.find(empty.path().string() + ": no .ply or .obj frames in this folder"), std::string::npos) << e.err;
}

TEST(CliRun, QuietAndVerbose) {
  auto r = run_cli({"run", "--scene", "cloth", "--size", "1", "--frames", "5", "--quiet", "--exit-zero"});
  EXPECT_EQ(r.status, 0);
  EXPECT_TRUE(table_rows(r.out).empty()) << r.out;
  EXPECT_NE(r.out.find("4 steps (frames 0 to 4)"), std::string::npos) << r.out;
  r = run_cli({"run", "--scene", "cloth", "--size", "1", "--frames", "5", "--verbose", "--exit-zero"});
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("columns: step k = frame k to k+1"), std::string::npos) << r.out;
  for (const char* column : {"vol tests", "VF tests", "EE tests", "front", "sprouted", "invalid", "rebuilt", "orphans"})
    EXPECT_NE(r.out.find(column), std::string::npos) << column;
  EXPECT_EQ(table_rows(r.out).size(), 4u) << r.out;
}

TEST(CliRun, MethodsPrintTheSameContactTotals) {
  std::string totals[4];
  int i = 0;
  for (const char* m : {"bruteforce", "traverse", "phc", "front"}) {
    const auto r = run_cli({"run", "--scene", "spheres", "--size", "1", "--frames", "9", "--substeps", "2", "--quiet",
                            "--method", m});
    ASSERT_EQ(r.status, 1) << r.err;
    const auto at = r.out.find("with contacts: ");
    ASSERT_NE(at, std::string::npos) << r.out;
    totals[i++] = r.out.substr(at, r.out.find('\n', at) - at);
  }
  for (int k = 1; k < 4; ++k) EXPECT_EQ(totals[0], totals[k]);
}

TEST(CliRun, TreesAndRepresentativeRulesPrintTheSameContactTotals) {
  std::string first;
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{}, {"--representatives", "canonical"}, {"--bvh", "median"},
        {"--bvh", "median", "--representatives", "leaf", "--leaf-size", "3"}, {"--leaf-size", "16"}, {"--leaf-size", "21"},
        {"--no-self-culling"}}) {
    std::vector<std::string> args{"run", "--scene", "spheres", "--size", "1", "--frames", "9", "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    ASSERT_EQ(r.status, 1) << r.err;
    const auto at = r.out.find("with contacts: ");
    ASSERT_NE(at, std::string::npos) << r.out;
    const std::string totals = r.out.substr(at, r.out.find('\n', at) - at);
    if (first.empty()) first = totals;
    EXPECT_EQ(totals, first);
  }
  for (const std::vector<std::string>& bad : {std::vector<std::string>{"--representatives", "paper"},
                                               {"--leaf-size", "22"}, {"--leaf-size", "0"}}) {
    std::vector<std::string> args{"run", "--scene", "spheres", "--size", "1", "--frames", "3"};
    args.insert(args.end(), bad.begin(), bad.end());
    const auto r = run_cli(args);
    EXPECT_EQ(r.status, 2) << bad[0] << " " << bad[1];
    EXPECT_NE(r.err.find(bad[0]), std::string::npos) << r.err;
  }
}

// A frame that cannot be read ends the run with status 2, but every step before it is in the
// files, which say they are incomplete; with --partial remove nothing is written.
TEST(CliRun, FailureAtTheLastFrameKeepsTheEarlierSteps) {
  ClothFiles cloth;
  std::vector<mccd::Positions> frames = cloth.frames();
  const std::string bad = write_frames(cloth.dir.path(), "bad", cloth.scene.meshes[0], frames);
  mccd::TriMesh broken = cloth.scene.meshes[0];
  broken.vertices = frames.back();
  std::swap(broken.faces[7][0], broken.faces[7][1]);
  mccd::write_ply(cloth.dir.file("bad005.ply"), broken);

  ScratchDir out("mccd_cli_partial");
  const std::string csv = out.file("c.csv"), stats = out.file("s.json");
  auto r = run_cli({"run", bad, "--contacts", csv, "--stats", stats});
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.err.find("bad005.ply (frame 5): face 7"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(csv + " keeps the 4 finished steps, marked incomplete"), std::string::npos) << r.err;
  EXPECT_EQ(table_rows(r.out).size(), 4u) << r.out;
  std::vector<std::string> rows = lines_of(slurp(csv));
  ASSERT_GE(rows.size(), 2u);
  EXPECT_EQ(rows.back().rfind("# incomplete: ", 0), 0u) << rows.back();
  EXPECT_NE(rows.back().find("bad005.ply"), std::string::npos) << rows.back();
  rows.erase(rows.begin());
  rows.pop_back();
  EXPECT_EQ(rows, library_rows(cloth.scene, 1, 4));
  const nlohmann::json s = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(s["complete"], false);
  EXPECT_EQ(s["steps"].size(), 4u);
  EXPECT_NE(s["stopped"].get<std::string>().find("bad005.ply"), std::string::npos);
  EXPECT_EQ(out.names(), (std::vector<std::string>{"c.csv", "s.json"}));

  ScratchDir none("mccd_cli_partial_remove");
  r = run_cli({"run", bad, "--contacts", none.file("c.csv"), "--stats", none.file("s.json"), "--partial", "remove"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("not written (--partial remove)"), std::string::npos) << r.err;
  EXPECT_TRUE(none.names().empty());
}

TEST(CliRun, BadInputBeforeTheFirstStepLeavesNoFile) {
  ScratchDir out("mccd_cli_bad");
  auto r = run_cli({"run", "/nonexistent/frame%03d.ply", "--contacts", out.file("c.csv")});
  EXPECT_EQ(r.status, 2);
  r = run_cli({"run", "--scene", "cloth", "--contacts", out.file("c.txt")});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("expected a .csv or .json file name"), std::string::npos) << r.err;
  // a picture is written at the end, but its folder is checked before any step runs
  r = run_cli({"run", "--scene", "cloth", "--contacts", out.file("c.csv"), "--image", out.file("no/such/p.png")});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_NE(r.err.find(out.file("no/such/p.png") + ": cannot write: no such folder"), std::string::npos) << r.err;
  EXPECT_TRUE(out.names().empty());
}

namespace {

/// Starts a long run writing into `out`, waits for its first table row, sends `sig`.
CliResult interrupt_run(const ScratchDir& out, int sig, const std::string& partial) {
  const ScratchDir capture("mccd_cli_capture");
  CliProcess p({"run", "--scene", "cloth", "--size", "20", "--frames", "400", "--method", "bruteforce", "--threads",
                "1", "--contacts", out.file("c.csv"), "--stats", out.file("s.json"), "--partial", partial},
               capture.path());
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (table_rows(p.out_so_far()).empty() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  p.signal(sig);
  return p.wait();
}

}  // namespace

TEST(CliRun, SigintKeepsTheFinishedStepsAndNoTemporary) {
  ScratchDir out("mccd_cli_sigint");
  const CliResult r = interrupt_run(out, SIGINT, "keep");
  EXPECT_EQ(r.signal, SIGINT) << r.status << r.err;
  EXPECT_NE(r.err.find("interrupted by SIGINT after "), std::string::npos) << r.err;
  EXPECT_EQ(out.names(), (std::vector<std::string>{"c.csv", "s.json"}));  // no ".c.csv.tmp..."
  const std::vector<std::string> rows = lines_of(slurp(out.file("c.csv")));
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.back().rfind("# incomplete: interrupted by SIGINT after ", 0), 0u) << rows.back();
  const nlohmann::json s = nlohmann::json::parse(slurp(out.file("s.json")));
  EXPECT_EQ(s["complete"], false);
  EXPECT_GE(s["steps"].size(), 1u);
  EXPECT_LT(s["steps"].size(), 399u);
}

TEST(CliRun, SigtermWithPartialRemoveLeavesNothing) {
  ScratchDir out("mccd_cli_sigterm");
  const CliResult r = interrupt_run(out, SIGTERM, "remove");
  EXPECT_EQ(r.signal, SIGTERM) << r.status << r.err;
  EXPECT_TRUE(out.names().empty());
}

TEST(CliDemo, WritesDemoPngWhereItRuns) {
  ScratchDir here("mccd_cli_demo");
  const auto r = run_cli({"demo", "--size", "16", "--frames", "20", "--image-size", "320x240"}, here.path());
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("dropped onto a ball"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" with contacts: "), std::string::npos) << r.out;  // genuine contacts
  EXPECT_NE(r.out.find("picture: demo.png"), std::string::npos) << r.out;
  EXPECT_EQ(slurp(here.path() / "demo.png").substr(1, 3), "PNG");
  EXPECT_EQ(here.names(), std::vector<std::string>{"demo.png"});
}

TEST(CliToiCheck, ClothFunnelEveryMethodMissesNothing) {
  const fs::path dir = data_dir() / "toi/cloth-funnel";
  MCCD_REQUIRE_DATA(dir);
  for (const char* m : {"bruteforce", "traverse", "phc", "front"}) {
    const auto r = run_cli({"toi-check", dir.string(), "--method", m});
    EXPECT_EQ(r.status, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("vertex-face: 92 listed pairs, 27 true; reported 27: found 27, missed 0"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("edge-edge  : 263 listed pairs, 107 true"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("  time "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("OK: 0 true pairs missed"), std::string::npos) << r.out;
  }
}

TEST(CliToiCheck, ClothBallFrontMissesNothing) {
  const fs::path dir = data_dir() / "toi/cloth-ball";
  MCCD_REQUIRE_DATA(dir);
  const auto r = run_cli({"toi-check", dir.string(), "--method", "front"});
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("found 19032, missed 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("found 94822, missed 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("front "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" MB)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("representatives: leaf"), std::string::npos) << r.out;
}

TEST(CliToiCheck, ClothFunnelPapersSettingReportsItsOrphanSet) {
  const fs::path dir = data_dir() / "toi/cloth-funnel";
  MCCD_REQUIRE_DATA(dir);
  const auto r = run_cli({"toi-check", dir.string(), "--bvh", "median"});
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("representatives: canonical; orphan set 430 VF + 1626 EE pairs"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("OK: 0 true pairs missed"), std::string::npos) << r.out;
}

// Issue 12, item 5: a folder without the data layout is refused naming the path, never with
// a raw filesystem exception.
TEST(CliToiCheck, RefusesFoldersWithoutTheLayoutNamingThePath) {
  ScratchDir empty("mccd_cli_toi");
  auto r = run_cli({"toi-check", "/nonexistent/scene"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "mccd toi-check: error: /nonexistent/scene: no such folder\n");
  r = run_cli({"toi-check", empty.path().string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find((empty.path() / "frames").string() + ": no such folder"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("filesystem"), std::string::npos) << r.err;
  fs::create_directories(empty.path() / "frames");
  r = run_cli({"toi-check", empty.path().string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find((empty.path() / "frames").string() + ": expected two .ply frames, found 0"), std::string::npos)
      << r.err;
  fs::create_directories(empty.path() / "file_not_folder");
  mccd::write_ply(empty.file("plain.ply"), mccd::make_folding_cloth(2, 2).meshes[0]);
  r = run_cli({"toi-check", empty.file("plain.ply")});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find(empty.file("plain.ply") + ": not a folder"), std::string::npos) << r.err;
  EXPECT_EQ(lines_of(r.err).size(), 1u);
}
