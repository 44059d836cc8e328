// The per-core probe of the harness (perf/harness/cores.h): which processors it lists, how it
// scales its rates, the speedup ceiling unequal cores leave, and what the report says of them.
#include <gtest/gtest.h>

#include <set>

#include "harness/cores.h"
#include "harness/report.h"

#if defined(__linux__)
#include <sched.h>
#endif

using namespace mccd::bench;

TEST(HarnessCores, EveryAllowedProcessorOnceRatesAgainstTheFastest) {
  const std::vector<CoreRate> rates = time_cores_alone(1);
#if defined(__linux__)
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  ASSERT_EQ(sched_getaffinity(0, sizeof allowed, &allowed), 0);
  ASSERT_EQ(rates.size(), static_cast<std::size_t>(CPU_COUNT(&allowed)));
  std::set<int> seen;
  double best_compute = 0, best_cache = 0;
  for (const CoreRate& r : rates) {
    EXPECT_TRUE(CPU_ISSET(r.cpu, &allowed)) << r.cpu;
    EXPECT_TRUE(seen.insert(r.cpu).second) << "cpu " << r.cpu << " twice";
    EXPECT_GT(r.compute, 0);
    EXPECT_GT(r.cache, 0);
    EXPECT_GT(r.compute_vs_best, 0);
    EXPECT_LE(r.compute_vs_best, 1);
    EXPECT_GT(r.cache_vs_best, 0);
    EXPECT_LE(r.cache_vs_best, 1);
    best_compute = std::max(best_compute, r.compute_vs_best);
    best_cache = std::max(best_cache, r.cache_vs_best);
  }
  EXPECT_EQ(best_compute, 1.0);  // the fastest over itself
  EXPECT_EQ(best_cache, 1.0);
#else
  EXPECT_TRUE(rates.empty());
#endif
}

TEST(HarnessCores, CeilingSumsTheFastestCoresOverTheOneThreadRunsCore) {
  std::vector<CoreRate> rates(3);
  const double vs[3] = {0.5, 1.0, 0.75};
  for (int i = 0; i < 3; ++i) rates[i].cpu = i, rates[i].compute_vs_best = vs[i];
  const Ceiling two = speedup_ceiling(rates, 2);  // the two fastest: 1.0 + 0.75
  EXPECT_DOUBLE_EQ(two.from_fastest, 1.75);
  EXPECT_DOUBLE_EQ(two.from_slowest, 1.75 / 0.5);
  const Ceiling all = speedup_ceiling(rates, 16);  // more threads than cores: all three
  EXPECT_DOUBLE_EQ(all.from_fastest, 2.25);
  EXPECT_DOUBLE_EQ(all.from_slowest, 4.5);
  const Ceiling none = speedup_ceiling({}, 2);
  EXPECT_EQ(none.from_fastest, 0);
  EXPECT_EQ(none.from_slowest, 0);
  // equal cores: P threads, P times one
  for (CoreRate& r : rates) r.compute_vs_best = 1;
  EXPECT_DOUBLE_EQ(speedup_ceiling(rates, 3).from_slowest, 3);
}

TEST(HarnessCores, ReportNamesEachCoreAndTheCeiling) {
  MachineInfo m;
  m.name = "test", m.cpu = "a CPU", m.hardware_threads = 2;
  EXPECT_EQ(report_markdown(m, {}, {}).find("Each core alone"), std::string::npos);  // not measured: not said
  m.cores_before.resize(2);
  m.cores_before[0].cpu = 0, m.cores_before[0].compute_vs_best = 0.5, m.cores_before[0].cache_vs_best = 0.9;
  m.cores_before[1].cpu = 1, m.cores_before[1].compute_vs_best = 1, m.cores_before[1].cache_vs_best = 1;
  m.cores_after = m.cores_before;
  const std::string text = report_markdown(m, {}, {});
  EXPECT_NE(text.find("cpu 0 0.50 / 0.90, cpu 1 1.00 / 1.00"), std::string::npos) << text;
  EXPECT_NE(text.find("1.50x-3.00x before"), std::string::npos) << text;
  EXPECT_EQ(core_rates_text({}), "n/a");
}
