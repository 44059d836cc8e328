// `mccd queries` on the benchmark sample queries: no false negative, exit status 0.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include "support/data.h"

namespace {

struct CliRun {
  int status;
  std::string out;
};

CliRun run_cli(const std::string& args) {
  const std::string cmd = mccd::test::cli_path() + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return {-1, ""};
  std::string out;
  std::array<char, 4096> buf;
  while (std::fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  const int raw = pclose(pipe);
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, out};
}

// The false-negative column of the row starting with `kind`.
long false_negatives(const std::string& out, const std::string& kind) {
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(kind, 0) != 0) continue;
    std::istringstream row(line);
    std::string name;
    long queries, positives, reported, fn;
    row >> name >> queries >> positives >> reported >> fn;
    return fn;
  }
  return -1;
}

}  // namespace

TEST(CcdCliQueries, SampleQueriesHaveNoFalseNegatives) {
  const auto dir = mccd::test::data_dir() / "sample-queries";
  MCCD_REQUIRE_DATA(dir);
  const CliRun r = run_cli("queries " + dir.string() + " --repeat 1");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(false_negatives(r.out, "vertex-face"), 0) << r.out;
  EXPECT_EQ(false_negatives(r.out, "edge-edge"), 0) << r.out;
  EXPECT_NE(r.out.find("3085"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("4194"), std::string::npos) << r.out;
}

TEST(CcdCliQueries, ClothFunnelWithJsonTruth) {
  const auto dir = mccd::test::data_dir() / "toi" / "cloth-funnel";
  MCCD_REQUIRE_DATA(dir / "queries" / "227ee.csv");
  const CliRun r = run_cli("queries " + (dir / "queries" / "227ee.csv").string() + " --kind ee --truth " +
                    (dir / "mma_bool" / "227ee_mma_bool.json").string() + " --repeat 1");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(false_negatives(r.out, "edge-edge"), 0) << r.out;
  EXPECT_NE(r.out.find("107"), std::string::npos) << r.out;  // positives
}

TEST(CcdCliQueries, TruthOfTheWrongLengthIsRefusedBeforeRunning) {
  const auto dir = mccd::test::data_dir() / "toi" / "cloth-funnel";
  MCCD_REQUIRE_DATA(dir / "queries" / "227vf.csv");
  const CliRun r = run_cli("queries " + (dir / "queries" / "227vf.csv").string() + " --kind vf --truth " +
                           (dir / "mma_bool" / "227ee_mma_bool.json").string() + " --repeat 1");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find("has 263 entries for 92 queries"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("false negative"), std::string::npos) << r.out;  // nothing was run
}

TEST(CcdCliQueries, MalformedFileIsRefusedWithItsLine) {
  const auto path = std::filesystem::temp_directory_path() / "mccd_cli_queries_bad.csv";
  {
    std::ofstream out(path);
    out << "1,2,3,4,5,8,0\n1,3,1,1,1,1,0\n";
  }
  const CliRun r = run_cli("queries " + path.string() + " --kind vf");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_NE(r.out.find(":2:"), std::string::npos) << r.out;  // 1/3: not a power-of-two denominator
  std::filesystem::remove(path);
}
