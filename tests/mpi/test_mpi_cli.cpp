// `mpirun -n 2 mccd ...` on localhost (built only with MCCD_MPI): a run split over two ranks
// writes the same contacts as one process, also when a frame in the second rank's range
// cannot be read; `mccd batch` over two ranks gives the same files as in one process, and both
// ranks take sequences.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "support/cli.h"
#include "support/sequences.h"

namespace fs = std::filesystem;
using namespace mccd::test;

namespace {

/// Runs `mpirun -n RANKS mccd ARGS...` (Open MPI allowed to run as root, and more ranks than
/// cores) and returns its status and output.
CliResult mpirun(int ranks, const std::vector<std::string>& args, const fs::path& capture) {
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  std::string cmd = std::string("'") + MCCD_MPIEXEC + "' -n " + std::to_string(ranks) + " " + MCCD_MPIEXEC_FLAGS +
                    " '" + MCCD_CLI_PATH + "'";
  for (const std::string& a : args) cmd += " '" + a + "'";
  const fs::path out = capture / "mpi_out.txt", err = capture / "mpi_err.txt";
  cmd += " >'" + out.string() + "' 2>'" + err.string() + "'";
  const int rc = std::system(cmd.c_str());
  CliResult r;
  r.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

/// Rows of a contacts CSV whose frame is at least `from`.
std::size_t rows_from(const std::string& csv, std::size_t from) {
  std::size_t n = 0;
  for (const std::string& l : lines_of(csv))
    if (!l.empty() && std::isdigit(static_cast<unsigned char>(l[0])) && std::stoul(l) >= from) ++n;
  return n;
}

}  // namespace

TEST(MpiRun, TwoRanksWriteTheContactsOfOneProcess) {
  ScratchDir dir("mccd_mpi_run");
  const std::vector<SequenceOnDisk> seqs = write_sequences(dir.path(), 6);
  const SequenceOnDisk& s = seqs[5];  // 11 frames: ranks 0 and 1 take steps 0-4 and 5-9
  for (const char* sub : {"1", "3"}) {
    SCOPED_TRACE(std::string("substeps ") + sub);
    const std::string c1 = dir.file("one.csv"), s1 = dir.file("one.json"), c2 = dir.file("two.csv"),
                      s2 = dir.file("two.json"), j1 = dir.file("one_c.json"), j2 = dir.file("two_c.json");
    const CliResult one = run_cli({"run", s.pattern, "--substeps", sub, "--contacts", c1, "--stats", s1, "--quiet"});
    ASSERT_EQ(one.status, 1) << one.err;
    const CliResult two =
        mpirun(2, {"run", s.pattern, "--substeps", sub, "--contacts", c2, "--stats", s2, "--quiet"}, dir.path());
    ASSERT_EQ(two.status, 1) << two.out << two.err;
    EXPECT_NE(two.out.find("2 ranks"), std::string::npos) << two.out;
    const std::string a = slurp(c1), b = slurp(c2);
    EXPECT_GT(rows_from(a, 5), 0u);  // the second rank's range has contacts to carry
    EXPECT_EQ(a, b);
    // the statistics: every step's contacts and earliest impact, and the summary's counts
    const nlohmann::json x = nlohmann::json::parse(slurp(s1)), y = nlohmann::json::parse(slurp(s2));
    ASSERT_EQ(x["steps"].size(), y["steps"].size());
    for (std::size_t i = 0; i < x["steps"].size(); ++i)
      for (const char* k : {"frame", "substep", "contacts", "vf_contacts", "ee_contacts", "earliest_toi"})
        EXPECT_EQ(x["steps"][i][k], y["steps"][i][k]) << i << " " << k;
    for (const char* k : {"steps", "steps_with_contacts", "vf_contacts", "ee_contacts", "first_impact"})
      EXPECT_EQ(x["summary"][k], y["summary"][k]) << k;
    EXPECT_EQ(y["complete"], true);
    // three ranks, JSON contacts
    ASSERT_EQ(run_cli({"run", s.pattern, "--substeps", sub, "--contacts", j1, "--quiet"}).status, 1);
    ASSERT_EQ(mpirun(3, {"run", s.pattern, "--substeps", sub, "--contacts", j2, "--quiet"}, dir.path()).status, 1);
    EXPECT_EQ(without_times(nlohmann::json::parse(slurp(j1))), without_times(nlohmann::json::parse(slurp(j2))));
  }
}

TEST(MpiRun, AFrameBrokenInTheSecondRanksRangeEndsTheRunAsInOneProcess) {
  ScratchDir dir("mccd_mpi_run");
  const std::vector<SequenceOnDisk> seqs = write_sequences(dir.path(), 6);
  const SequenceOnDisk& s = seqs[5];
  { std::ofstream(frame_file(s.pattern, 10), std::ios::trunc) << "ply\nbroken\n"; }
  const std::string c1 = dir.file("one.csv"), c2 = dir.file("two.csv");
  const CliResult one = run_cli({"run", s.pattern, "--contacts", c1, "--quiet"});
  const CliResult two = mpirun(2, {"run", s.pattern, "--contacts", c2, "--quiet"}, dir.path());
  EXPECT_EQ(one.status, 2);
  EXPECT_EQ(two.status, 2) << two.err;
  EXPECT_NE(two.err.find("frame010.ply"), std::string::npos) << two.err;
  EXPECT_NE(two.err.find("rank 1 of 2"), std::string::npos) << two.err;
  const std::string a = slurp(c1);
  EXPECT_NE(a.find("# incomplete:"), std::string::npos);
  EXPECT_GT(rows_from(a, 5), 0u);  // rank 1's steps 5 to 8 were kept, with contacts
  EXPECT_EQ(a, slurp(c2));
}

TEST(MpiBatch, TwoRanksGiveTheFilesOfOneProcessAndShareTheSequences) {
  ScratchDir dir("mccd_mpi_batch");
  const std::vector<SequenceOnDisk> seqs = write_sequences(dir.path() / "in", 6);
  { std::ofstream(frame_file(seqs[2].pattern, 3), std::ios::trunc) << "not a mesh\n"; }
  {
    std::ofstream m(dir.file("list.txt"));
    for (const auto& s : seqs) m << s.pattern << "\n";
  }
  const std::string one = dir.file("one"), two = dir.file("two");
  const CliResult a = run_cli({"batch", dir.file("list.txt"), "--out", one});
  const CliResult b = mpirun(2, {"batch", dir.file("list.txt"), "--out", two}, dir.path());
  EXPECT_EQ(a.status, 2) << a.err;
  EXPECT_EQ(b.status, 2) << b.out << b.err;
  EXPECT_NE(b.err.find("list.txt:3"), std::string::npos) << b.err;
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(two)) names.insert(e.path().filename().string());
  EXPECT_EQ(names.size(), 6u * 2 + 2);  // nothing temporary
  for (const auto& s : seqs) {
    SCOPED_TRACE(s.name);
    const std::string c = s.name + ".contacts.csv", st = s.name + ".stats.json";
    EXPECT_EQ(slurp(fs::path(one) / c), slurp(fs::path(two) / c));
    EXPECT_FALSE(slurp(fs::path(two) / c).empty());
    EXPECT_EQ(without_times(nlohmann::json::parse(slurp(fs::path(one) / st))),
              without_times(nlohmann::json::parse(slurp(fs::path(two) / st))));
  }
  // the summaries agree but for the times and ranks; both ranks ran sequences
  const std::vector<std::string> x = lines_of(slurp(fs::path(one) / "summary.csv")),
                                 y = lines_of(slurp(fs::path(two) / "summary.csv"));
  ASSERT_EQ(x.size(), 7u);
  ASSERT_EQ(y.size(), 7u);
  std::set<std::string> ranks;
  for (std::size_t i = 1; i < 7; ++i) {
    auto cut = [](const std::string& l) {  // fields 0-8 (up to the first impact), and the error
      std::size_t p = 0;
      for (int k = 0; k < 9; ++k) p = l.find(',', p) + 1;
      const std::size_t after_rank = l.find(',', l.find(',', p) + 1) + 1;
      return std::make_pair(l.substr(0, p), l.substr(after_rank));
    };
    EXPECT_EQ(cut(x[i]), cut(y[i]));
    std::size_t p = 0;
    for (int k = 0; k < 10; ++k) p = y[i].find(',', p) + 1;
    ranks.insert(y[i].substr(p, y[i].find(',', p) - p));
    EXPECT_EQ(y[i].find(",failed,") != std::string::npos, i == 3) << y[i];
  }
  EXPECT_EQ(ranks, (std::set<std::string>{"0", "1"}));
}
