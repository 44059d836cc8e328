// Runs the built `mccd run` end to end on small generated sequences: the table and summary,
// the contacts and statistics files against the library, the exit statuses, a run failing at
// its last frame, and SIGINT / SIGTERM (nothing temporary left behind).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <limits>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
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

/// The columns of a table row: step, VF, EE, first impact (which may be "3 + 7.49e-6"), time.
struct Row {
  std::size_t step = 0;
  std::string vf, ee, first;
};
Row parse_row(const std::string& line) {
  std::istringstream in(line);
  Row r;
  in >> r.step >> r.vf >> r.ee >> r.first;
  std::string plus, t;
  if (in >> plus && plus == "+" && in >> t) r.first += " + " + t;
  return r;
}

/// The step of the first table row with contacts (the number of rows when none has).
std::size_t first_row_with_contacts(const std::string& out) {
  const std::vector<std::string> rows = table_rows(out);
  for (const std::string& line : rows) {
    const Row r = parse_row(line);
    if (r.vf != "0" || r.ee != "0") return r.step;
  }
  return rows.size();
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
  // the legend (the frames' files, what a step and the times are), then the header
  ASSERT_GE(lines.size(), 4u);
  EXPECT_EQ(lines[1], "frames: frame 0 = frame000.ply, frame 1 = frame001.ply, ..., frame 5 = frame005.ply");
  EXPECT_EQ(lines[2].rfind("step k = frame k to k+1; first impact = frame time k + t", 0), 0u) << lines[2];
  for (const char* column : {"step", "VF", "EE", "first impact", "time"})
    EXPECT_NE(lines[3].find(column), std::string::npos) << lines[3];
  EXPECT_EQ(table_rows(r.out).size(), 5u) << r.out;

  const std::vector<std::string> expected = library_rows(cloth.scene, 1, 5);
  ASSERT_FALSE(expected.empty());
  std::vector<std::string> rows = lines_of(slurp(csv));
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.front(), "frame,substep,kind,mesh_a,feature_a,mesh_b,feature_b,v0,v1,v2,v3,toi,t");
  rows.erase(rows.begin());
  EXPECT_EQ(rows, expected);
  // steps named by their files (issue 36): the summary and the first-impact line
  EXPECT_NE(r.out.find("5 steps (frame000.ply to frame005.ply)"), std::string::npos) << r.out;
  const std::string digits = std::to_string(expected.size());
  std::string count;  // grouped by thousands, as printed
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) count.push_back(',');
    count.push_back(digits[i]);
  }
  count.append(" contacts (");
  EXPECT_NE(r.out.find(count), std::string::npos) << r.out;
  // the first impact's step is the first row with contacts, named by its two files
  const std::size_t first_step = first_row_with_contacts(r.out);
  ASSERT_LT(first_step, 5u) << r.out;
  char step_files[96];
  std::snprintf(step_files, sizeof step_files, " (step %zu: frame%03zu.ply to frame%03zu.ply)\n", first_step, first_step,
                first_step + 1);
  EXPECT_NE(r.out.find("first impact at frame time "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(step_files), std::string::npos) << step_files << "\n" << r.out;
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
  EXPECT_NE(r.out.find("no collision in 3 steps (calm000.ply to calm003.ply)"), std::string::npos) << r.out;

  r = run_cli({"run", "--scene", "cloth", "--size", "1", "--frames", "6", "--quiet"});
  EXPECT_EQ(r.status, 1) << r.err;
  r = run_cli({"run", "--scene", "cloth", "--size", "1", "--frames", "6", "--quiet", "--exit-zero"});
  EXPECT_EQ(r.status, 0) << r.err;
  r = run_cli({"run", (dir.path() / "missing%03d.ply").string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
}

namespace {

/// Two triangles of one mesh, written as `frames` frame files: a large one lying at z = 0 and
/// a small one whose apex is `gap` above the plane in the even frames and 0.5 lower in the odd
/// ones. In every step the apex goes through the large triangle: downwards at local time
/// 2 gap (steps 0, 2, ...), upwards at 1 - 2 gap (steps 1, 3, ...).
std::string write_piercing_frames(const fs::path& dir, double gap, int frames) {
  mccd::TriMesh m;
  m.vertices = mccd::Positions{mccd::Vec3(-1, -1, 0), mccd::Vec3(1, -1, 0),  mccd::Vec3(0, 1, 0),
                               mccd::Vec3(0, 0, gap),  mccd::Vec3(0.1, 0, 1), mccd::Vec3(0, 0.1, 1)};
  m.faces = {{0, 1, 2}, {3, 4, 5}};
  std::vector<mccd::Positions> f(std::size_t(frames), m.vertices);
  for (std::size_t i = 1; i < f.size(); i += 2)
    for (std::size_t v = 3; v < 6; ++v) f[i](v, 2) -= 0.5;
  return write_frames(dir, "pierce", m, f);
}

}  // namespace

// Issue 36: an impact 2.5e-5 into a step used to print as 0.0000 (the frame itself), and one
// just before the next frame may not round up to it.
TEST(CliRun, TimesOfImpactKeepTheirDigits) {
  ScratchDir dir("mccd_cli_toi_digits");
  const std::string pattern = write_piercing_frames(dir.path(), 1.25e-5, 4);
  const std::string csv = dir.file("c.csv");
  const auto r = run_cli({"run", pattern, "--contacts", csv});
  ASSERT_EQ(r.status, 1) << r.err;
  // every step's earliest impact, with every digit, from the contacts file
  std::vector<double> earliest(3, std::numeric_limits<double>::infinity());
  std::vector<std::string> csv_rows = lines_of(slurp(csv));
  ASSERT_GE(csv_rows.size(), 4u);
  for (std::size_t i = 1; i < csv_rows.size(); ++i) {
    std::vector<std::string> field;
    std::istringstream in(csv_rows[i]);
    for (std::string f; std::getline(in, f, ',');) field.push_back(f);
    ASSERT_EQ(field.size(), 13u) << csv_rows[i];
    const std::size_t step = std::stoul(field[0]);
    ASSERT_LT(step, 3u);
    earliest[step] = std::min(earliest[step], std::stod(field[11]));
  }
  EXPECT_NEAR(earliest[0], 2.5e-5, 1e-6);
  EXPECT_NEAR(earliest[1], 2 - 2.5e-5, 1e-6);
  EXPECT_NEAR(earliest[2], 2 + 2.5e-5, 1e-6);

  const std::vector<std::string> rows = table_rows(r.out);
  ASSERT_EQ(rows.size(), 3u) << r.out;
  for (std::size_t k = 0; k < 3; ++k) {
    const Row row = parse_row(rows[k]);
    ASSERT_EQ(row.step, k);
    // the printed time read back: the step's frame, then the time within it to its digits
    const std::size_t plus = row.first.find(" + ");
    const double t = plus == std::string::npos ? std::stod(row.first) - double(k) : std::stod(row.first.substr(plus + 3));
    EXPECT_EQ(std::floor(std::stod(row.first)), double(k)) << rows[k];
    EXPECT_NEAR(t, earliest[k] - double(k), 5e-3 * (earliest[k] - double(k))) << rows[k];
  }
  EXPECT_EQ(parse_row(rows[0]).first.substr(0, 3), "2.5") << rows[0];
  EXPECT_NE(parse_row(rows[0]).first.find("e-5"), std::string::npos) << rows[0];
  EXPECT_EQ(parse_row(rows[1]).first.substr(0, 6), "1.9999") << rows[1];
  EXPECT_EQ(parse_row(rows[2]).first.substr(0, 8), "2 + 2.5e") << rows[2];
  EXPECT_NE(r.out.find("first impact at frame time " + parse_row(rows[0]).first +
                       " (step 0: pierce000.ply to pierce001.ply)\n"),
            std::string::npos)
      << r.out;
}

// Issue 36: a run that fails says so in its summary (where and why), never "no collision in 0
// steps"; the exit status stays 2 and the error stays on stderr.
TEST(CliRun, AFailedRunSaysInItsSummaryWhereAndWhy) {
  ClothFiles cloth;
  const std::vector<mccd::Positions> frames = cloth.frames();
  const std::string bad = write_frames(cloth.dir.path(), "bad", cloth.scene.meshes[0], frames);
  mccd::TriMesh broken = cloth.scene.meshes[0];
  broken.vertices = frames[1];
  std::swap(broken.faces[7][0], broken.faces[7][1]);
  mccd::write_ply(cloth.dir.file("bad001.ply"), broken);
  auto r = run_cli({"run", bad});
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.err.find("bad001.ply (frame 1): face 7 is"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("run stopped at step 0 (bad000.ply to bad001.ply), 0 of 5 steps finished: " +
                       cloth.dir.file("bad001.ply") + " (frame 1): face 7 is"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("\nno step finished\n"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("no collision"), std::string::npos) << r.out;
  EXPECT_TRUE(table_rows(r.out).empty()) << r.out;

  // stopped after steps without contacts: "in the finished steps", named by their files
  ScratchDir dir("mccd_cli_failed_calm");
  mccd::TriMesh grid = mccd::make_folding_cloth(6, 2).meshes[0];
  std::vector<mccd::Positions> calm(4, grid.vertices);
  for (std::size_t f = 0; f < calm.size(); ++f)
    for (std::size_t v = 0; v < calm[f].rows(); ++v) calm[f](v, 0) += 0.1 * double(f);
  const std::string pattern = write_frames(dir.path(), "calm", grid, calm);
  mccd::TriMesh short_mesh = grid;
  short_mesh.vertices = calm[3];
  short_mesh.faces.pop_back();
  mccd::write_ply(dir.file("calm003.ply"), short_mesh);
  r = run_cli({"run", pattern, "--quiet"});
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("run stopped at step 2 (calm002.ply to calm003.ply), 2 of 3 steps finished: " +
                       dir.file("calm003.ply") + " (frame 3): has "),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("\nno collision in the 2 finished steps (calm000.ply to calm002.ply)\n"), std::string::npos)
      << r.out;

  // stopped after steps with contacts (the cloth's last step): their totals and first impact
  std::vector<mccd::Positions> more = frames;
  more.push_back(frames.back());
  const std::string longer = write_frames(cloth.dir.path(), "more", cloth.scene.meshes[0], more);
  broken.vertices = frames.back();
  mccd::write_ply(cloth.dir.file("more006.ply"), broken);
  r = run_cli({"run", longer, "--quiet"});
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("run stopped at step 5 (more005.ply to more006.ply), 5 of 6 steps finished: " +
                       cloth.dir.file("more006.ply") + " (frame 6): face 7 is"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("\n5 finished steps (more000.ply to more005.ply), 1 with contacts: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" (step 4: more004.ply to more005.ply)\n"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("first impact at frame time 4"), r.out.find("\nfirst impact at") + 1) << r.out;
}

// Issue 36: a path that is not there is named as such, not counted as a frame.
TEST(CliRun, AMissingPathIsNamedAsSuch) {
  ScratchDir dir("mccd_cli_missing");
  auto r = run_cli({"run", "nonexistent"}, dir.path());
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "mccd run: error: nonexistent: cannot open: No such file or directory\n");
  EXPECT_EQ(r.out, "");
  mccd::write_ply(dir.file("a.ply"), mccd::make_folding_cloth(2, 2).meshes[0]);
  r = run_cli({"run", "a.ply", "b.ply"}, dir.path());
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "mccd run: error: b.ply: cannot open: No such file or directory\n");
  // one frame that is there is still one too few
  r = run_cli({"run", "a.ply"}, dir.path());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("need at least two frames, got 1 (a.ply)"), std::string::npos) << r.err;
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
  EXPECT_NE(r.out.find("run stopped at step 4 (bad004.ply to bad005.ply), 4 of 5 steps finished: "), std::string::npos)
      << r.out;
  // the cloth folds onto itself in its last step only
  EXPECT_NE(r.out.find("\nno collision in the 4 finished steps (bad000.ply to bad004.ply)\n"), std::string::npos)
      << r.out;
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
  // the step --help promises: (frames - 1) * 2 / 5
  EXPECT_NE(r.out.find("picture: demo.png (step 7 at frame time 7"), std::string::npos) << r.out;
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
