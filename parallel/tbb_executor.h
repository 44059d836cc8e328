#pragma once
/// @file Internal: the engine's loops on oneTBB, and the executor (core/executor.h) that hands
/// them to the serial algorithms of core/. Every loop runs in the calling thread's arena; a
/// range of at most one grain runs on the calling thread, without a task.
///
/// Work and span: while a stage runs with a WorkSpanRecorder installed on its thread
/// (StageClock, SceneOptions::work_span), every outermost loop of the stage times its tasks:
/// the stage's work is its serial time plus all its tasks, its span its serial time plus the
/// longest task of each loop (loops inside a task are part of that task).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_invoke.h>
#include <oneapi/tbb/partitioner.h>

#include <mccd/core/executor.h>
#include <mccd/core/stats.h>

namespace mccd::detail {

/// The parallel loops of one stage, added up (see the file comment).
class WorkSpanRecorder {
 public:
  void add_loop(double wall, double tasks, double longest) {
    parallel_wall_ += wall;
    tasks_ += tasks;
    longest_ += longest;
  }
  /// The stage's work and span, from its wall time.
  WorkSpan finish(double stage_wall) const {
    const double serial = std::max(0.0, stage_wall - parallel_wall_);
    return {serial + tasks_, serial + longest_};
  }

 private:
  double parallel_wall_ = 0, tasks_ = 0, longest_ = 0;
};

/// The recorder of the stage this thread runs (nullptr: not measured), and whether this thread
/// is inside a task of a measured loop (its own loops are then part of that task).
inline thread_local WorkSpanRecorder* tl_work_span = nullptr;
inline thread_local bool tl_in_task = false;

/// The tasks of one measured loop, timed from any thread.
class LoopTimer {
 public:
  using Clock = std::chrono::steady_clock;
  explicit LoopTimer(WorkSpanRecorder& recorder) : recorder_(recorder), start_(Clock::now()) {}
  ~LoopTimer() {
    recorder_.add_loop(seconds(Clock::now() - start_), tasks_.load(std::memory_order_relaxed),
                       longest_.load(std::memory_order_relaxed));
  }
  LoopTimer(const LoopTimer&) = delete;
  LoopTimer& operator=(const LoopTimer&) = delete;
  /// Runs f() as one task of the loop.
  template <class F>
  void task(const F& f) {
    struct InTask {
      bool was = tl_in_task;
      InTask() { tl_in_task = true; }
      ~InTask() { tl_in_task = was; }
    } in_task;
    const auto t = Clock::now();
    f();
    const double d = seconds(Clock::now() - t);
    tasks_.fetch_add(d, std::memory_order_relaxed);
    double m = longest_.load(std::memory_order_relaxed);
    while (d > m && !longest_.compare_exchange_weak(m, d, std::memory_order_relaxed)) {
    }
  }

 private:
  static double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }
  WorkSpanRecorder& recorder_;
  Clock::time_point start_;
  std::atomic<double> tasks_{0}, longest_{0};
};

/// The recorder of an outermost loop on this thread, or nullptr.
inline WorkSpanRecorder* loop_recorder() { return tl_in_task ? nullptr : tl_work_span; }

/// body(begin, end) over chunks of about `grain` of [0, n) under `partitioner` (timed when the
/// stage is measured).
template <class Body, class Partitioner>
void chunked_for(std::size_t n, std::size_t grain, const Body& body, const Partitioner& partitioner) {
  if (n <= grain) {
    if (n) body(std::size_t(0), n);
    return;
  }
  const tbb::blocked_range<std::size_t> range(0, n, grain);
  if (WorkSpanRecorder* recorder = loop_recorder()) {
    LoopTimer timer(*recorder);
    // Each grain is a task of its own: the finest piece a scheduler could hand out, whatever
    // chunks this run's partitioner made (on one thread it makes few and large ones).
    tbb::parallel_for(
        range,
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t b = r.begin(); b < r.end(); b += grain) {
            const std::size_t e = std::min(r.end(), b + grain);
            timer.task([&] { body(b, e); });
          }
        },
        partitioner);
    return;
  }
  tbb::parallel_for(range, [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); }, partitioner);
}

/// body(i) for every i in [0, n), one task per index under `partitioner` (blocks of a front,
/// tasks of a traversal).
template <class Body, class Partitioner>
void for_each_index(std::size_t n, const Body& body, const Partitioner& partitioner) {
  chunked_for(
      n, 1,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i != e; ++i) body(i);
      },
      partitioner);
}

/// a() and b(), possibly at once (two tasks of one loop when measured).
template <class A, class B>
void invoke_pair(const A& a, const B& b) {
  if (WorkSpanRecorder* recorder = loop_recorder()) {
    LoopTimer timer(*recorder);
    tbb::parallel_invoke([&] { timer.task(a); }, [&] { timer.task(b); });
    return;
  }
  tbb::parallel_invoke(a, b);
}

/// Installs `recorder` (nullptr: none) on this thread while a stage runs, and times the stage.
class StageClock {
 public:
  using Clock = std::chrono::steady_clock;
  explicit StageClock(WorkSpanRecorder* recorder)
      : recorder_(recorder), was_(tl_work_span), was_in_task_(tl_in_task), start_(Clock::now()) {
    tl_work_span = recorder;
    tl_in_task = false;  // a stage run from inside another's task (stolen) measures its own loops
  }
  ~StageClock() {
    tl_work_span = was_;
    tl_in_task = was_in_task_;
  }
  StageClock(const StageClock&) = delete;
  StageClock& operator=(const StageClock&) = delete;
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  /// The stage's work and span so far (zero when not measured).
  WorkSpan work_span() const { return recorder_ ? recorder_->finish(seconds()) : WorkSpan{}; }

 private:
  WorkSpanRecorder* recorder_;
  WorkSpanRecorder* was_;
  bool was_in_task_;
  Clock::time_point start_;
};

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
  void invoke(Task a, Task b) const override { invoke_pair(a, b); }
};

inline const Executor& tbb_executor() {
  static const TbbExecutor executor;
  return executor;
}

}  // namespace mccd::detail
