#include "harness/cores.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <numeric>
#include <thread>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

namespace mccd::bench {

namespace {

using Clock = std::chrono::steady_clock;

#if defined(__linux__)
/// Seconds `work` took on a thread pinned to processor `cpu` (negative: it could not be pinned).
double pinned_seconds(int cpu, const std::function<void()>& work) {
  double seconds = -1;
  std::thread t([&] {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    if (pthread_setaffinity_np(pthread_self(), sizeof set, &set) != 0) return;
    std::this_thread::yield();  // run from here on the processor asked for
    const auto t0 = Clock::now();
    work();
    seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  });
  t.join();
  return seconds;
}
#endif

}  // namespace

double independent_chains(std::uint64_t rounds) {
  double x[16];
  for (int i = 0; i < 16; ++i) x[i] = i + 1;
  const double c = 0.9999999, d = 1e-7;
  for (std::uint64_t i = 0; i < rounds; ++i)
    for (double& v : x) v = v * c + d;
  return std::accumulate(x, x + 16, 0.0);
}

std::uint64_t sum_passes(const std::vector<std::uint64_t>& a, int passes) {
  std::uint64_t s = 0;
  for (int p = 0; p < passes; ++p)
    for (std::uint64_t v : a) s += v;
  return s;
}

std::vector<CoreRate> time_cores_alone(int rounds) {
  std::vector<CoreRate> rates;
#if defined(__linux__)
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (sched_getaffinity(0, sizeof allowed, &allowed) != 0) return rates;
  constexpr std::uint64_t kRounds = 3'000'000;  // 96 M floating-point operations
  const std::vector<std::uint64_t> array(std::size_t(2) << 17, 1);  // 2 MiB
  constexpr int kPasses = 24;
  volatile double fsink = 0;
  volatile std::uint64_t isink = 0;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (!CPU_ISSET(cpu, &allowed)) continue;
    CoreRate r;
    r.cpu = cpu;
    bool pinned = true;
    for (int k = 0; k < std::max(1, rounds) && pinned; ++k) {
      const double c = pinned_seconds(cpu, [&] { fsink = fsink + independent_chains(kRounds); });
      const double m = pinned_seconds(cpu, [&] { isink = isink + sum_passes(array, kPasses); });
      pinned = c > 0 && m > 0;
      if (!pinned) break;
      r.compute = std::max(r.compute, 32.0 * double(kRounds) / c * 1e-9);
      r.cache = std::max(r.cache, double(kPasses) * double(array.size() * sizeof(std::uint64_t)) / m * 1e-9);
    }
    if (pinned) rates.push_back(r);
  }
  double best_compute = 0, best_cache = 0;
  for (const CoreRate& r : rates) {
    best_compute = std::max(best_compute, r.compute);
    best_cache = std::max(best_cache, r.cache);
  }
  for (CoreRate& r : rates) {
    r.compute_vs_best = r.compute / best_compute;
    r.cache_vs_best = r.cache / best_cache;
  }
#else
  (void)rounds;
#endif
  return rates;
}

std::string core_rates_text(const std::vector<CoreRate>& rates) {
  if (rates.empty()) return "n/a";
  std::string s;
  for (const CoreRate& r : rates) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%scpu %d %.2f / %.2f", s.empty() ? "" : ", ", r.cpu, r.compute_vs_best,
                  r.cache_vs_best);
    s += buf;
  }
  return s;
}

Ceiling speedup_ceiling(const std::vector<CoreRate>& rates, int threads) {
  if (rates.empty() || threads < 1) return {};
  std::vector<double> v;
  for (const CoreRate& r : rates) v.push_back(r.compute_vs_best);
  std::sort(v.begin(), v.end(), std::greater<>());
  const std::size_t n = std::min(v.size(), static_cast<std::size_t>(threads));
  const double sum = std::accumulate(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n), 0.0);
  return {sum / v.back(), sum / v.front()};
}

}  // namespace mccd::bench
