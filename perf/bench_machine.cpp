// How this machine's cores scale, without mccd: the same fixed work on every thread, run on
// 1, 2, 4, ... threads at once, compute-bound (independent floating-point chains held in
// registers: perf/harness/cores.h) and cache-bound (each thread sums its own array over and
// over). A per-thread rate that falls as threads are added (a lower clock with every core
// busy, a shared cache's bandwidth, a host's other guests) caps every program's speedup there:
// the ceiling on P threads is P x rate(P) / rate(1). The 16-core figures of bench_core read
// against it. Then each core alone (perf/harness/cores.h): unequal cores cap a speedup too.
//   bench_machine [--threads 1,2,4,8,16] [--rounds K] [--kib N]
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "harness/cli.h"
#include "harness/cores.h"
#include "harness/summary.h"

using namespace mccd::bench;

namespace {

using Clock = std::chrono::steady_clock;

/// Seconds each of `threads` threads took for `work(t)`, all started together.
template <class Work>
std::vector<double> run_together(int threads, const Work& work) {
  std::vector<double> seconds(static_cast<std::size_t>(threads));
  std::atomic<int> ready{0};
  std::atomic<bool> go{false};
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      ready.fetch_add(1);
      while (!go.load(std::memory_order_acquire)) std::this_thread::yield();
      const auto t0 = Clock::now();
      work(t);
      seconds[static_cast<std::size_t>(t)] = std::chrono::duration<double>(Clock::now() - t0).count();
    });
  while (ready.load() < threads) std::this_thread::yield();
  go.store(true, std::memory_order_release);
  for (std::thread& th : pool) th.join();
  return seconds;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> threads;
  int rounds = 5, kib = 2048;
  CLI::App app{"Measures how this machine's cores scale without mccd: fixed work per thread on 1, 2, 4, ... threads\n"
               "at once, compute-bound and cache-bound; the per-thread rate against one thread's, and the speedup\n"
               "ceiling it sets (threads x that ratio).",
               "bench_machine"};
  app.add_option("--threads", threads, "thread counts (default: 1 and the powers of two up to the hardware threads)")
      ->delimiter(',')
      ->check(integer_in(1, kMaxThreads));
  add_repeats(app, "--rounds", rounds, "rounds, each running every thread count in turn");
  app.add_option("--kib", kib, "KiB each thread sums in the cache-bound test, 16 to 1048576")
      ->check(integer_in(16, 1 << 20))
      ->capture_default_str();
  if (const int rc = parse_command_line(app, argc, argv); rc >= 0) return rc;
  if (threads.empty()) {
    const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    for (int t = 1; t < hw; t *= 2) threads.push_back(t);
    threads.push_back(hw);
  }
  threads.push_back(1);  // the base of every ratio
  std::sort(threads.begin(), threads.end());
  threads.erase(std::unique(threads.begin(), threads.end()), threads.end());

  try {
    constexpr std::uint64_t kRounds = 10'000'000;  // compute: 320 M floating-point operations a thread
    const std::size_t words = static_cast<std::size_t>(kib) * 1024 / sizeof(std::uint64_t);
    const int passes = std::max(1, static_cast<int>((std::size_t(1) << 31) / (words * sizeof(std::uint64_t))));
    const int most = *std::max_element(threads.begin(), threads.end());
    std::vector<std::vector<std::uint64_t>> arrays(static_cast<std::size_t>(most));
    for (auto& a : arrays) a.assign(words, 1);
    std::vector<double> sink(static_cast<std::size_t>(most));
    std::vector<std::uint64_t> isink(static_cast<std::size_t>(most));
    // per thread count: per-round median per-thread rates (Gflop/s and GB/s)
    std::vector<std::vector<double>> flops(threads.size()), bytes(threads.size());
    for (int r = 0; r < rounds; ++r)
      for (std::size_t i = 0; i < threads.size(); ++i) {
        const int t = threads[i];
        const auto c = run_together(t, [&](int k) { sink[static_cast<std::size_t>(k)] = independent_chains(kRounds); });
        const auto s = run_together(t, [&](int k) {
          isink[static_cast<std::size_t>(k)] = sum_passes(arrays[static_cast<std::size_t>(k)], passes);
        });
        flops[i].push_back(32.0 * double(kRounds) / median(c) * 1e-9);
        bytes[i].push_back(double(passes) * double(words * sizeof(std::uint64_t)) / median(s) * 1e-9);
      }
    std::printf("%zu threads most, %d rounds (medians), cache-bound: %d KiB a thread, %d passes\n", static_cast<std::size_t>(most),
                rounds, kib, passes);
    std::printf("%8s  %14s %9s %8s  %14s %9s %8s\n", "threads", "Gflop/s thread", "vs 1", "ceiling", "GB/s thread",
                "vs 1", "ceiling");
    const double f1 = median(flops[0]), b1 = median(bytes[0]);
    for (std::size_t i = 0; i < threads.size(); ++i) {
      const double f = median(flops[i]), b = median(bytes[i]);
      std::printf("%8d  %14.2f %9.3f %7.1fx  %14.2f %9.3f %7.1fx\n", threads[i], f, f / f1, threads[i] * f / f1, b,
                  b / b1, threads[i] * b / b1);
    }
    // Each core on its own: a virtual machine's cores need not be equally fast.
    const std::vector<CoreRate> cores = time_cores_alone(rounds);
    if (!cores.empty()) {
      std::printf("\neach core alone (one thread pinned to it, best of %d rounds), against the fastest core\n", rounds);
      std::printf("%8s  %14s %9s  %14s %9s\n", "cpu", "Gflop/s", "vs best", "GB/s", "vs best");
      for (const CoreRate& c : cores)
        std::printf("%8d  %14.2f %9.3f  %14.2f %9.3f\n", c.cpu, c.compute, c.compute_vs_best, c.cache,
                    c.cache_vs_best);
      for (int t : threads) {
        if (t == 1) continue;
        const Ceiling c = speedup_ceiling(cores, t);
        std::printf("ceiling on %d threads from the cores' compute rates: %.2fx over a 1-thread run on the fastest "
                    "core, %.2fx over one on the slowest\n",
                    t, c.from_fastest, c.from_slowest);
      }
    }
    double keep = 0;
    for (double v : sink) keep += v;
    for (std::uint64_t v : isink) keep += double(v);
    if (keep == -1) std::printf("\n");  // never: the results are used
  } catch (const std::exception& e) {
    return report_failure("bench_machine", e);
  }
  return 0;
}
