// `mccd --help`, `--version`, `COMMAND --help` for every command, and the one-line refusal
// (exit status 2) of unknown commands and options and of every out-of-range value.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "support/cli.h"

using mccd::test::lines_of;
using mccd::test::run_cli;

namespace {

/// Every option each command documents.
const std::map<std::string, std::vector<std::string>>& command_options() {
  static const std::map<std::string, std::vector<std::string>> m = {
      {"demo", {"--size", "--frames", "--method", "--threads", "--image", "--image-step", "--image-size", "--camera",
                "--colored", "--quiet", "--verbose"}},
      {"info", {"FILE"}},
      {"run", {"FRAMES", "--scene", "--size", "--frames", "--method", "--substeps", "--min-distance", "--volume",
               "--rebuild-sprout", "--rebuild-invalid", "--threads", "--contacts", "--stats", "--partial",
               "--exit-zero", "--image", "--image-step", "--image-size", "--camera", "--colored", "--quiet",
               "--verbose"}},
      {"toi-check", {"DIR", "--method", "--min-distance", "--threads"}},
      {"queries", {"PATH", "--kind", "--truth", "--min-distance", "--repeat", "--verbose"}},
  };
  return m;
}

}  // namespace

TEST(CliHelp, TopLevelListsEveryCommandAndTheExitStatuses) {
  const auto r = run_cli({"--help"});
  EXPECT_EQ(r.status, 0) << r.err;
  for (const auto& [name, options] : command_options()) EXPECT_NE(r.out.find("  " + name + " "), std::string::npos) << name;
  EXPECT_NE(r.out.find("Exit status: 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("mccd demo"), std::string::npos) << r.out;
}

namespace {
/// `text` with every run of spaces and line breaks as one space (the help is wrapped).
std::string flat(const std::string& text) {
  std::string out;
  for (const char c : text)
    if (c != ' ' && c != '\n') out.push_back(c);
    else if (!out.empty() && out.back() != ' ') out.push_back(' ');
  return out;
}
}  // namespace

// Issue 36: the demo's help says one thing about the step its picture shows (the demo's own
// behaviour is checked in CliDemo and CliImage), and run's help another.
TEST(CliHelp, ThePictureStepIsTheOneTheCommandDraws) {
  const std::string demo = flat(run_cli({"demo", "--help"}).out);
  EXPECT_NE(demo.find("draws the picture (demo.png, or --image) of step (frames - 1) * 2 / 5, two fifths of the way "
                      "through (step 17 of the default 45 frames)"),
            std::string::npos)
      << demo;
  EXPECT_NE(demo.find("--image FILE.png|FILE.jpg draw the meshes at step (frames - 1) * 2 / 5"), std::string::npos)
      << demo;
  EXPECT_EQ(demo.find("earliest impact of the first sub-step with contacts"), std::string::npos) << demo;
  const std::string run = flat(run_cli({"run", "--help"}).out);
  EXPECT_NE(run.find("--image FILE.png|FILE.jpg draw the meshes at the first contact (the earliest impact of the "
                     "first sub-step with contacts) as a PNG (.png) or JPEG (.jpg, .jpeg"),
            std::string::npos)
      << run;
}

TEST(CliHelp, Version) {
  const auto r = run_cli({"--version"});
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out.rfind("mccd ", 0), 0u) << r.out;
  EXPECT_NE(r.out.find_first_of("0123456789"), std::string::npos) << r.out;
}

TEST(CliHelp, EveryCommandDocumentsEveryOption) {
  for (const auto& [name, options] : command_options()) {
    const auto r = run_cli({name, "--help"});
    EXPECT_EQ(r.status, 0) << name << ": " << r.err;
    EXPECT_EQ(r.err, "") << name;
    EXPECT_NE(r.out.find("Usage: mccd " + name), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("Exit status"), std::string::npos) << name;
    for (const std::string& opt : options) {
      // the option's line carries a description after its name
      auto at = r.out.find("  " + opt);
      if (at == std::string::npos) at = r.out.find("," + opt);  // after a short form: -q,--quiet
      ASSERT_NE(at, std::string::npos) << name << " " << opt << "\n" << r.out;
      const std::string line = r.out.substr(at, r.out.find('\n', at) - at);
      const std::string next = r.out.substr(r.out.find('\n', at) + 1, 40);
      EXPECT_TRUE(line.size() > opt.size() + 12 || next.rfind("        ", 0) == 0) << name << " " << opt;
    }
    // help lines are wrapped for a terminal
    for (const std::string& line : lines_of(r.out)) EXPECT_LE(line.size(), 110u) << name << ": " << line;
  }
}

TEST(CliHelp, NoArgumentsPrintsUsageAndFails) {
  const auto r = run_cli({});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("Usage: mccd"), std::string::npos) << r.err;
}

TEST(CliHelp, UnknownCommandsAndOptionsAreOneLine) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"frobnicate"}, "mccd: error: unknown command 'frobnicate'"},
      {{"--bogus"}, "mccd: error: unknown option --bogus"},
      {{"run", "--scene", "cloth", "--bogus"}, "mccd run: error: unknown option --bogus (see 'mccd run --help')"},
      {{"info", "--bogus", "x.ply"}, "mccd info: error: unknown option --bogus"},
      {{"toi-check", "a", "b"}, "mccd toi-check: error: unexpected argument b"},
      {{"queries", "--kind", "vv", "x.csv"}, "mccd queries: error: --kind"},
      {{"run", "--scene", "cloth", "--frames"}, "--frames"},
      {{"info"}, "FILE is required"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.status, 2) << expected;
    EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "") << expected;
  }
}

// Issue 12, item 4: every numeric option is bounded, with a message naming it and the range,
// and nothing starts running (no value exhausts memory or runs until killed).
TEST(CliHelp, EveryNumericOptionIsBounded) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"run", "--scene", "cloth", "--substeps", "2000000000"}, "--substeps: must be from 1 to 1000, got '2000000000'"},
      {{"run", "--scene", "cloth", "--substeps", "0"}, "--substeps: must be from 1 to 1000"},
      {{"run", "--scene", "cloth", "--substeps", "2.5"}, "--substeps: expected an integer from 1 to 1000, got '2.5'"},
      {{"run", "--scene", "cloth", "--substeps", "99999999999999999999999"}, "--substeps: must be from 1 to 1000"},
      {{"run", "--scene", "cloth", "--size", "100000"}, "--size: must be from 1 to 200"},
      {{"run", "--scene", "cloth", "--size", "200", "--frames", "5000"}, "--size times --frames may be at most 20000"},
      {{"run", "--scene", "cloth", "--frames", "1"}, "--frames: must be from 2 to 5000"},
      {{"run", "--scene", "cloth", "--frames", "1e9"}, "--frames: expected an integer"},
      {{"run", "--scene", "cloth", "--threads", "0"}, "--threads: must be from 1 to 1024"},
      {{"run", "--scene", "cloth", "--threads", "100000"}, "--threads: must be from 1 to 1024"},
      {{"run", "--scene", "cloth", "--min-distance", "-1"}, "--min-distance: must be at least 0, got '-1'"},
      {{"run", "--scene", "cloth", "--min-distance", "nan"}, "--min-distance: expected a finite number"},
      {{"run", "--scene", "cloth", "--min-distance", "inf"}, "--min-distance: expected a finite number"},
      {{"run", "--scene", "cloth", "--size", "1", "--min-distance", "1e30"},
       "--min-distance 1e+30 is larger than 1% of the scene's size"},
      {{"run", "--scene", "cloth", "--rebuild-sprout", "0"}, "--rebuild-sprout: must be greater than 0 to 100"},
      {{"run", "--scene", "cloth", "--rebuild-invalid", "1e300"}, "--rebuild-invalid: must be greater than 0 to 100"},
      {{"run", "--scene", "cloth", "--image-size", "100000x100000"}, "--image-size: expected WIDTHxHEIGHT"},
      {{"run", "--scene", "cloth", "--image-size", "4096x4096"}, "at most 8.4 million pixels"},
      {{"run", "--scene", "cloth", "--image-step", "-1"}, "--image-step: must be from 0"},
      {{"run", "--scene", "cloth", "--frames", "5", "--image", "x.png", "--image-step", "4"},
       "--image-step 4: the run has steps 0 to 3"},
      {{"run", "--scene", "cloth", "--image", "x.png", "--camera", "1,2"}, "--camera: expected EX,EY,EZ"},
      {{"run", "--scene", "cloth", "--method", "sideways"}, "unknown method 'sideways'"},
      {{"run", "--scene", "cloth", "--volume", "sphere"}, "--volume"},
      {{"demo", "--size", "100000"}, "--size: must be from 10 to 200"},
      {{"demo", "--frames", "100000"}, "--frames: must be from 2 to 300"},
      {{"toi-check", "x", "--threads", "-3"}, "--threads: must be from 1 to 1024"},
      {{"toi-check", "x", "--min-distance", "-0.5"}, "--min-distance: must be at least 0"},
      {{"queries", "x.csv", "--repeat", "1000000000"}, "--repeat: must be from 1 to 1000"},
      {{"queries", "x.csv", "--min-distance", "1e999"}, "--min-distance: expected a finite number"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = run_cli(args);
    EXPECT_EQ(r.status, 2) << expected << "\n" << r.out;
    EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << "expected: " << expected << "\ngot: " << r.err;
  }
}
