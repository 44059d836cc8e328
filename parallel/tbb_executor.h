#pragma once
/// @file Internal: the engine's loops on oneTBB, and the executor (core/executor.h) that hands
/// them to the serial algorithms of core/. Every loop runs in the calling thread's arena; a
/// range of at most one grain runs on the calling thread, without a task.
#include <cstddef>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_invoke.h>
#include <oneapi/tbb/partitioner.h>

#include <mccd/core/executor.h>

namespace mccd::detail {

/// body(begin, end) over chunks of about `grain` of [0, n) under `partitioner`.
template <class Body, class Partitioner>
void chunked_for(std::size_t n, std::size_t grain, const Body& body, const Partitioner& partitioner) {
  if (n <= grain) {
    if (n) body(std::size_t(0), n);
    return;
  }
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, grain),
      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); }, partitioner);
}

/// Chunks under a static partition: equal work per item (the set-up's one-off loops).
template <class Body>
void static_for(std::size_t n, std::size_t grain, const Body& body) {
  chunked_for(n, grain, body, tbb::static_partitioner());
}

/// Chunks dealt out dynamically: a thread that the host stalls (a busy virtual machine) leaves
/// its chunks to the others.
template <class Body>
void dynamic_for(std::size_t n, std::size_t grain, const Body& body) {
  chunked_for(n, grain, body, tbb::simple_partitioner());
}

/// The executor of the engine: static_for / dynamic_for and tbb::parallel_invoke.
class TbbExecutor final : public Executor {
 public:
  void for_chunks(std::size_t n, std::size_t grain, Chunk body, Schedule schedule) const override {
    if (grain == 0) grain = 1;
    if (schedule == Schedule::Static)
      ::mccd::detail::static_for(n, grain, body);
    else
      ::mccd::detail::dynamic_for(n, grain, body);
  }
  void invoke(Task a, Task b) const override { tbb::parallel_invoke(a, b); }
};

inline const Executor& tbb_executor() {
  static const TbbExecutor executor;
  return executor;
}

}  // namespace mccd::detail
