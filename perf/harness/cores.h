#pragma once
/// @file Each core of the machine on its own: one thread pinned to one processor at a time,
/// the same fixed work on each. On a virtual machine the host can give one virtual core less of
/// a physical one than another (another guest on its sibling hyperthread, time slices), and
/// then a P-thread run over a 1-thread run is capped by the sum of the P cores' rates over the
/// rate of the core the 1-thread run had, not by P. bench_machine prints the rates; bench_core
/// measures them before and after its sweep and writes them into its report.
#include <cstdint>
#include <string>
#include <vector>

namespace mccd::bench {

/// Compute-bound work: 16 independent chains x = x c + d, `rounds` rounds (32 floating-point
/// operations a round), enough to fill a core's floating-point units (which a sibling
/// hyperthread shares). Returns the chains' sum, so that nothing is optimised away.
double independent_chains(std::uint64_t rounds);
/// Cache-bound work: `passes` sums over `a`.
std::uint64_t sum_passes(const std::vector<std::uint64_t>& a, int passes);

/// One processor's rates alone, relative to the fastest processor's (1 for the fastest).
struct CoreRate {
  int cpu = 0;           ///< the processor's number (sched_getaffinity)
  double compute = 0;    ///< independent floating-point chains: Gflop/s
  double cache = 0;      ///< sums over a 2 MiB array: GB/s
  double compute_vs_best = 0, cache_vs_best = 0;
};

/// The processors this process may run on, each in turn with one thread pinned to it, `rounds`
/// times (the best of the rounds for each). Empty where threads cannot be pinned (not Linux).
std::vector<CoreRate> time_cores_alone(int rounds = 2);

/// "cpu 0 1.00 / 1.00, cpu 1 0.71 / 0.93" (compute / cache against the fastest), or "n/a".
std::string core_rates_text(const std::vector<CoreRate>& rates);

/// The speedup ceiling on `threads` threads that unequal cores leave, for a run whose chunks
/// go to whichever thread is free: the sum of the `threads` fastest cores' compute rates over
/// the slowest core's (a 1-thread run may land on any core), and over the fastest's.
struct Ceiling {
  double from_slowest = 0, from_fastest = 0;
};
Ceiling speedup_ceiling(const std::vector<CoreRate>& rates, int threads);

}  // namespace mccd::bench
