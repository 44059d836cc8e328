// `mccd batch` in one process (no MPI needed): six generated sequences, one with a frame that
// cannot be read, give the same per-sequence files as `mccd run` on each, and a summary (CSV
// and Markdown) that marks the broken one failed while the others complete.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "support/cli.h"
#include "support/sequences.h"

namespace fs = std::filesystem;
using namespace mccd::test;

namespace {

/// Splits a CSV line without quoted commas.
std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out(1);
  for (char c : line)
    if (c == ',')
      out.emplace_back();
    else
      out.back().push_back(c);
  return out;
}

}  // namespace

TEST(CliBatch, SameFilesAsRunAndASummaryThatMarksTheBrokenSequence) {
  ScratchDir dir("mccd_cli_batch");
  const std::vector<SequenceOnDisk> seqs = write_sequences(dir.path() / "in", 6);
  // sequence 3: frame 4 is not a mesh
  const std::string broken = frame_file(seqs[3].pattern, 4);
  { std::ofstream(broken, std::ios::trunc) << "ply\nthis is not a frame\n"; }
  {
    std::ofstream m(dir.file("list.txt"));
    m << "# six cloths\n";
    for (std::size_t i = 0; i < seqs.size(); ++i)
      m << seqs[i].pattern << (i == 5 ? " --substeps 2" : "") << "\n";
  }
  const std::string out = dir.file("out");
  const CliResult b = run_cli({"batch", dir.file("list.txt"), "--out", out});
  EXPECT_EQ(b.status, 2) << b.out << b.err;  // one sequence failed
  EXPECT_NE(b.err.find("list.txt:5"), std::string::npos) << b.err;  // its manifest line
  EXPECT_NE(b.err.find("frame004.ply"), std::string::npos) << b.err;

  // every sequence's files equal those of `mccd run` on it
  for (std::size_t i = 0; i < seqs.size(); ++i) {
    SCOPED_TRACE(seqs[i].name);
    const std::string c = dir.file(seqs[i].name + ".csv"), s = dir.file(seqs[i].name + ".json");
    std::vector<std::string> args = {"run", seqs[i].pattern, "--contacts", c, "--stats", s, "--quiet"};
    if (i == 5) args.insert(args.end(), {"--substeps", "2"});
    const CliResult r = run_cli(args);
    EXPECT_EQ(r.status, i == 3 ? 2 : 1) << r.err;
    const std::string bc = slurp(fs::path(out) / (seqs[i].name + ".contacts.csv"));
    ASSERT_FALSE(bc.empty());
    EXPECT_EQ(bc, slurp(c));
    EXPECT_EQ(without_times(nlohmann::json::parse(slurp(fs::path(out) / (seqs[i].name + ".stats.json")))),
              without_times(nlohmann::json::parse(slurp(s))));
    if (i == 3) {
      EXPECT_NE(bc.find("# incomplete:"), std::string::npos);
    }
  }

  // the summary: one row per sequence in manifest order, the broken one failed
  const std::vector<std::string> rows = lines_of(slurp(fs::path(out) / "summary.csv"));
  ASSERT_EQ(rows.size(), 7u);
  EXPECT_EQ(rows[0], "sequence,line,status,frames,triangles,steps,steps_with_contacts,contacts,first_impact,seconds,rank,error");
  for (std::size_t i = 0; i < seqs.size(); ++i) {
    const std::vector<std::string> f = fields(rows[i + 1]);
    ASSERT_GE(f.size(), 12u) << rows[i + 1];
    EXPECT_EQ(f[0], seqs[i].name);
    EXPECT_EQ(f[1], std::to_string(i + 2));  // after the comment line
    EXPECT_EQ(f[2], i == 3 ? "failed" : "ok") << rows[i + 1];
    EXPECT_EQ(f[3], std::to_string(seqs[i].frames));
    EXPECT_EQ(f[5], std::to_string(i == 3 ? 3 : seqs[i].frames - 1));  // steps before the broken frame
    if (i != 3) {
      EXPECT_NE(f[7], "0");  // every folding cloth has contacts by its end
    }
    EXPECT_EQ(f[10], "0");  // one process: rank 0
    if (i == 3) {
      EXPECT_NE(rows[i + 1].find("frame004.ply"), std::string::npos);
    }
  }
  const std::string md = slurp(fs::path(out) / "summary.md");
  EXPECT_NE(md.find("| cloth3 | 5 | failed |"), std::string::npos) << md;
  EXPECT_NE(md.find("| cloth0 | 2 | ok |"), std::string::npos) << md;

  // nothing else in the folder: no temporary, no half-written file
  std::set<std::string> names, expected = {"summary.csv", "summary.md"};
  for (const auto& e : fs::directory_iterator(out)) names.insert(e.path().filename().string());
  for (const auto& s : seqs) expected.insert({s.name + ".contacts.csv", s.name + ".stats.json"});
  EXPECT_EQ(names, expected);
}

TEST(CliBatch, RefusesABadManifestLineBeforeAnyWork) {
  ScratchDir dir("mccd_cli_batch");
  { std::ofstream(dir.file("list.txt")) << "a/frame%03d.ply\nb/frame%03d.ply --substeps zero\n"; }
  const CliResult r = run_cli({"batch", dir.file("list.txt"), "--out", dir.file("out")});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("list.txt:2"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(fs::path(dir.file("out")) / "summary.csv"));
}
