// The harness's arithmetic: the Amdahl fit of the serial fraction, medians and spreads of
// runs, and the per-scene figures drawn from them.
#include <gtest/gtest.h>

#include <cmath>

#include "harness/report.h"
#include "harness/summary.h"

using namespace mccd;
using namespace mccd::bench;

namespace {

RunRecord run(const std::string& scene, Method m, int threads, int index, double ms) {
  RunRecord r;
  r.scene = scene, r.method = m, r.threads = threads, r.run = index, r.steps = 4, r.intervals = 2, r.wall_ms = 2 * ms;
  r.sum.t_update = 2e-3 * ms / 4;  // a quarter of the step
  r.sum.volume_tests = m == Method::Traverse ? 4000 : 2400;
  r.sum.vf_tests = 300, r.sum.ee_tests = 500, r.sum.vf_contacts = 30, r.sum.ee_contacts = 10;
  r.rebuilds = 2, r.rebuild_front = 1600, r.rebuild_adjacent = 400, r.max_front_bytes = 3'000'000;
  return r;
}

}  // namespace

TEST(HarnessSummary, SerialFractionFromTwoThreadCounts) {
  // T(2) = 0.6 T(1): s = 2 * 0.6 - 1 = 0.2
  EXPECT_NEAR(serial_fraction({{1, 100}, {2, 60}}), 0.2, 1e-12);
  EXPECT_NEAR(amdahl_speedup(0.2, 16), 1 / (0.2 + 0.8 / 16), 1e-12);
  EXPECT_NEAR(amdahl_speedup(0.0, 16), 16, 1e-12);
  // slower on two threads than on one: everything serial; faster than linear: nothing
  EXPECT_EQ(serial_fraction({{1, 100}, {2, 120}}), 1.0);
  EXPECT_EQ(serial_fraction({{1, 100}, {2, 40}}), 0.0);
  EXPECT_TRUE(std::isnan(serial_fraction({{2, 60}})));
  EXPECT_TRUE(std::isnan(serial_fraction({{1, 60}})));
}

TEST(HarnessSummary, SerialFractionFitsExactAmdahlData) {
  const double s = 0.07;
  std::vector<std::pair<int, double>> points;
  for (int p : {1, 2, 3, 4, 8, 16}) points.emplace_back(p, 50 * (s + (1 - s) / p));
  EXPECT_NEAR(serial_fraction(points), s, 1e-12);
}

TEST(HarnessSummary, MediansSpreadsAndSceneFigures) {
  std::vector<RunRecord> runs;
  for (Method m : {Method::Traverse, Method::Phc, Method::Fbd})
    for (int t : {1, 2}) {
      const double base = (m == Method::Fbd ? 10.0 : 20.0) / (t == 1 ? 1.0 : 1.6);
      runs.push_back(run("s", m, t, 0, 1000));  // the warm-up never counts in the times
      for (int k = 1; k <= 3; ++k) runs.push_back(run("s", m, t, k, base * (1 + 0.1 * (k - 2))));
    }
  // the paper's configuration: one counted run each of traverse and fbd on 1 thread
  for (Method m : {Method::Traverse, Method::Fbd}) {
    RunRecord p = run("s", m, 1, 0, 50);
    p.config = "paper";
    p.sum.volume_tests = m == Method::Traverse ? 8000 : 4000;
    p.rebuild_front = 3000, p.rebuild_adjacent = 1000;
    runs.push_back(p);
  }
  const std::vector<VariantSummary> v = summarize(runs);
  ASSERT_EQ(v.size(), 8u);
  const VariantSummary& fbd1 = v[4];
  EXPECT_EQ(fbd1.method, Method::Fbd);
  EXPECT_EQ(fbd1.runs, 3);
  EXPECT_NEAR(fbd1.median_ms[kStep], 10.0, 1e-9);  // per frame interval: 2 intervals
  EXPECT_NEAR(fbd1.min_ms, 9.0, 1e-9);
  EXPECT_NEAR(fbd1.max_ms, 11.0, 1e-9);
  EXPECT_NEAR(fbd1.median_ms[kUpdate], 2.5, 1e-9);
  // paired by round: run k on 2 threads against run k on 1 (both 1.6x apart in every round)
  EXPECT_NEAR(fbd1.paired_speedup, 1.0, 1e-12);
  const VariantSummary& fbd2 = v[5];
  ASSERT_EQ(fbd2.threads, 2);
  EXPECT_NEAR(fbd2.paired_speedup, 1.6, 1e-9);
  EXPECT_NEAR(fbd2.paired_min, 1.6, 1e-9);
  EXPECT_NEAR(fbd2.paired_max, 1.6, 1e-9);

  Workload w;
  w.name = "s";
  w.mesh.faces.resize(12);
  w.positions.resize(5);
  w.intervals = 4;
  const SceneSummary s = summarize_scene(w, v);
  EXPECT_EQ(s.method, Method::Fbd);
  ASSERT_EQ(s.threads, (std::vector<int>{1, 2}));
  EXPECT_NEAR(s.serial[kStep], 2 / 1.6 - 1, 1e-9);
  EXPECT_NEAR(s.volume_tests_traverse, 1000, 1e-9);
  EXPECT_NEAR(s.volume_tests_method, 600, 1e-9);
  // figures 7 and 9 in the paper's configuration, from the paper runs only
  EXPECT_NEAR(s.paper_volume_traverse, 2000, 1e-9);
  EXPECT_NEAR(s.paper_volume_fbd, 1000, 1e-9);
  EXPECT_NEAR(s.front_nodes, 1500, 1e-9);
  EXPECT_NEAR(s.front_adjacent, 500, 1e-9);
  EXPECT_NEAR(s.front_mb, 3.0, 1e-12);
  EXPECT_NEAR(s.elementary_tests / s.contacts, 20.0, 1e-9);
  EXPECT_NEAR(s.phc_ms_1, 20.0, 1e-9);
  ASSERT_EQ(s.paired.size(), 2u);
  EXPECT_NEAR(s.paired[1], 1.6, 1e-9);
}

TEST(HarnessSummary, PairedSpeedupTakesEachRoundOnItsOwn) {
  // The machine slows down by half from the 4-thread run of round 2 to the 1-thread run of
  // round 3: the medians' ratio reads 150 / 26 = 5.8x, each round on its own 4x (but round 2).
  std::vector<RunRecord> runs;
  const double one[] = {100, 200, 200, 100}, four[] = {25, 30, 50, 25};
  for (int k = 1; k <= 4; ++k) {
    runs.push_back(run("s", Method::Fbd, 1, k, one[k - 1]));
    runs.push_back(run("s", Method::Fbd, 4, k, four[k - 1]));
  }
  runs.push_back(run("s", Method::Fbd, 4, 5, 26));  // a round with no 1-thread run pairs with nothing
  const std::vector<VariantSummary> v = summarize(runs);
  ASSERT_EQ(v.size(), 2u);
  const VariantSummary& four_threads = v[1];
  EXPECT_EQ(four_threads.runs, 5);
  EXPECT_NEAR(v[0].median_ms[kStep] / four_threads.median_ms[kStep], 150.0 / 26, 1e-9);
  EXPECT_NEAR(four_threads.paired_speedup, 4.0, 1e-9);  // of 4, 6.67, 4, 4
  EXPECT_NEAR(four_threads.paired_min, 4.0, 1e-9);
  EXPECT_NEAR(four_threads.paired_max, 200.0 / 30, 1e-9);
  EXPECT_NEAR(v[0].paired_speedup, 1.0, 1e-12);
  // a variant with no 1-thread runs at all
  std::vector<RunRecord> alone{run("t", Method::Fbd, 2, 1, 10)};
  EXPECT_TRUE(std::isnan(summarize(alone)[0].paired_speedup));
}

TEST(HarnessSummary, SearchAndSelfIsTheirSharedPartOfTheStep) {
  // The search and the self stage overlap (each 9 ms of wall time on a 10 ms step whose update,
  // refit and join take 1, 0.5 and 0.25 ms): the stage they form together is the rest of the
  // engine's time, 8.25 ms, not their sum; per frame interval (2 intervals) half of it.
  RunRecord r;
  r.intervals = 2, r.wall_ms = 10.5;
  r.sum.t_update = 1e-3, r.sum.t_refit = 0.5e-3, r.sum.t_contacts = 0.25e-3, r.sum.t_total = 10e-3;
  r.sum.t_front = 9e-3, r.sum.t_self = 9e-3;
  EXPECT_NEAR(stage_ms(r, kSearchAndSelf), 8.25 / 2, 1e-12);
  EXPECT_NEAR(stage_ms(r, kSearch), 4.5, 1e-12);
  EXPECT_NEAR(stage_ms(r, kStep), 5.25, 1e-12);
  EXPECT_STREQ(stage_name(kSearchAndSelf), "search + self");
  EXPECT_FALSE(stage_scales_alone(kSearch));
  EXPECT_FALSE(stage_scales_alone(kOrphans));
  EXPECT_TRUE(stage_scales_alone(kSearchAndSelf));
  EXPECT_TRUE(stage_scales_alone(kStep));
}

TEST(HarnessReport, MachineNameIsAFolderName) {
  const std::string name = default_machine_name();
  EXPECT_FALSE(name.empty());
  for (char c : name) EXPECT_TRUE(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.') << name;
  EXPECT_EQ(name.back(), 't');
}

TEST(HarnessSummary, WorkSpanPredictsEachStageAndTheTimeOutside) {
  // 2 intervals, 10 ms in all: update W 2 / S 1, refit W 1 / S 1 (serial), the branch W 4 /
  // S 0.5, join W 1 / S 0.25; 2 ms outside the stages. On 4 threads: 2 + (1 + 1/4) + 1 +
  // (0.5 + 3.5/4) + (0.25 + 0.75/4) = 6.0625 ms, per interval half of it.
  RunRecord r;
  r.intervals = 2, r.wall_ms = 10;
  r.sum.ws_update = {2e-3, 1e-3};
  r.sum.ws_refit = {1e-3, 1e-3};
  r.sum.ws_branch = {4e-3, 0.5e-3};
  r.sum.ws_join = {1e-3, 0.25e-3};
  EXPECT_NEAR(predicted_ms(r, 4), 6.0625 / 2, 1e-12);
  EXPECT_NEAR(predicted_ms(r, 1), 5.0, 1e-12);  // one thread: the measured time itself
  EXPECT_NEAR(r.sum.ws_branch.predict(1e9), 0.5e-3, 1e-11);  // never below the span
  // Scaled to a measured 2-thread time of 4 ms: on 2 threads 2 + 1.5 + 1 + 2.25 + 0.625 =
  // 7.375 ms, per interval 3.6875; 4 x 3.03125 / 3.6875 on 4 threads, 4 itself on 2.
  EXPECT_NEAR(predicted_from_ms(r, 4, 2, 4.0), 4.0 * 3.03125 / 3.6875, 1e-12);
  EXPECT_NEAR(predicted_from_ms(r, 2, 2, 4.0), 4.0, 1e-12);
}

TEST(HarnessReport, WorkSpanTableShowsTheWorkOnTwoThreadsBesideOne) {
  // One scene measured on 1 thread and on 2 (2 intervals): the search's work 8 -> 10 ms, so
  // 4 -> 5 ms a frame, 1.25 times; the update's 2 -> 1.5 ms, 0.75 times.
  RunRecord one;
  one.scene = "s", one.method = Method::Fbd, one.intervals = 2, one.wall_ms = 12, one.config = "work-span";
  one.sum.ws_update = {2e-3, 0.5e-3};
  one.sum.ws_search = {8e-3, 1e-3};
  one.sum.ws_branch = one.sum.ws_search;
  RunRecord two = one;
  two.threads = 2, two.config = "work-span-2";
  two.sum.ws_update = {1.5e-3, 0.5e-3};
  two.sum.ws_search = {10e-3, 1e-3};
  two.sum.ws_branch = two.sum.ws_search;
  MachineInfo m;
  m.name = "test", m.cpu = "a CPU", m.hardware_threads = 2;
  const std::string text = report_markdown(m, {}, summarize({one, two}));
  EXPECT_NE(text.find("| s | fbd | search | 4.000 | 0.500 | 8.0 | 5.000 | 1.25 |"), std::string::npos) << text;
  EXPECT_NE(text.find("| s | fbd | update | 1.000 | 0.250 | 4.0 | 0.750 | 0.75 |"), std::string::npos) << text;
  // without the 2-thread runs the columns say so
  const std::string alone = report_markdown(m, {}, summarize({one}));
  EXPECT_NE(alone.find("| s | fbd | search | 4.000 | 0.500 | 8.0 | - | - |"), std::string::npos) << alone;
  // the 2-thread record is no row of its own in the prediction table
  EXPECT_EQ(text.find("| s | fbd | 2 | "), std::string::npos) << text;
}
