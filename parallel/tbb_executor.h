#pragma once
/// @file Internal: the engine's loops on oneTBB, and the executor (core/executor.h) that hands
/// them to the serial algorithms of core/. Every loop runs in the calling thread's arena; a
/// range of at most one grain runs on the calling thread, without a task.
///
/// Work and span: while a stage runs with a WorkSpanRecorder installed on its thread
/// (StageClock, SceneOptions::work_span), every outermost loop of the stage times its tasks:
/// the stage's work is its serial time plus all its tasks, its span its serial time plus the
/// longest path through each loop: a task's span is its serial time plus the span of every loop
/// it runs inside (a recursive parallel_invoke or a loop in a loop's task counts at every depth).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <type_traits>
#include <vector>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_invoke.h>
#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

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

/// The task this thread runs inside a measured loop: its nested loops' wall time and span.
struct TaskFrame {
  double nested_wall = 0, nested_span = 0;
};

/// The recorder of the stage this thread runs (nullptr: not measured), and the measured task
/// this thread is inside (nullptr: none; its own loops are then the stage's outermost).
inline thread_local WorkSpanRecorder* tl_work_span = nullptr;
inline thread_local TaskFrame* tl_frame = nullptr;

/// The tasks of one measured loop, timed from any thread. A loop inside a task adds its wall
/// time and span to that task's frame: the task's span is its own serial time plus the span of
/// each loop it ran (the longest path through the nested loops, measured on one thread).
class LoopTimer {
 public:
  using Clock = std::chrono::steady_clock;
  explicit LoopTimer(WorkSpanRecorder& recorder) : recorder_(recorder), parent_(tl_frame), start_(Clock::now()) {}
  ~LoopTimer() {
    const double wall = seconds(Clock::now() - start_), longest = longest_.load(std::memory_order_relaxed);
    if (parent_) {
      parent_->nested_wall += wall;
      parent_->nested_span += longest;
    } else {
      recorder_.add_loop(wall, tasks_.load(std::memory_order_relaxed), longest);
    }
  }
  LoopTimer(const LoopTimer&) = delete;
  LoopTimer& operator=(const LoopTimer&) = delete;
  /// Runs f() as one task of the loop.
  template <class F>
  void task(const F& f) {
    TaskFrame frame;
    struct Enter {
      TaskFrame* was = tl_frame;
      explicit Enter(TaskFrame* f) { tl_frame = f; }
      ~Enter() { tl_frame = was; }
    } enter(&frame);
    const auto t = Clock::now();
    f();
    const double d = seconds(Clock::now() - t);
    const double span = std::max(0.0, d - frame.nested_wall) + frame.nested_span;
    tasks_.fetch_add(d, std::memory_order_relaxed);
    double m = longest_.load(std::memory_order_relaxed);
    while (span > m && !longest_.compare_exchange_weak(m, span, std::memory_order_relaxed)) {
    }
  }

 private:
  static double seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }
  WorkSpanRecorder& recorder_;
  TaskFrame* parent_;
  Clock::time_point start_;
  std::atomic<double> tasks_{0}, longest_{0};
};

/// The recorder of the stage this thread runs, or nullptr.
inline WorkSpanRecorder* loop_recorder() { return tl_work_span; }

/// Chunks of a loop dealt out to its workers: each worker takes the chunks of its own run of
/// them, in order (neighbouring chunks share data: a front's cache-ordered blocks, a leaf's
/// lanes), then takes what is left of the others' runs, one chunk at a time. A chunk costs
/// one atomic add on a counter that, until the end of the loop, only its owner touches.
class ChunkDealer {
 public:
  ChunkDealer(std::size_t chunks, std::size_t workers) : workers_(workers), runs_(workers) {
    for (std::size_t w = 0; w < workers; ++w) {
      runs_[w].next.store(chunks * w / workers, std::memory_order_relaxed);
      runs_[w].end = chunks * (w + 1) / workers;
    }
  }
  /// Worker `me` runs take(chunk) for every chunk it wins, until none is left or the loop is
  /// cancelled (a chunk threw).
  template <class Take>
  void work(std::size_t me, const Take& take) {
    for (std::size_t d = 0; d < workers_; ++d) {
      Run& r = runs_[(me + d) % workers_];
      for (std::size_t c; (c = r.next.fetch_add(1, std::memory_order_relaxed)) < r.end;) {
        if (tbb::is_current_task_group_canceling()) return;
        take(c);
      }
    }
  }

 private:
  struct alignas(64) Run {  // a cache line each: a worker's adds do not slow the others'
    std::atomic<std::size_t> next{0};
    std::size_t end = 0;
  };
  std::size_t workers_;
  std::vector<Run> runs_;
};

/// body(begin, end) over the chunks [k grain, (k + 1) grain) of [0, n), dealt out to as many
/// workers as the arena has threads (ChunkDealer; fewer for fewer chunks). A chunk runs
/// isolated: a thread that waits inside it for a loop of its own runs only that loop's
/// tasks, never another worker of this loop (which would hold the chunk until the loop ends).
/// Timed per chunk when the stage is measured. With one worker (one thread, or one chunk) the
/// chunks run in order on the calling thread, without a task.
template <class Body>
void dealt_for(std::size_t n, std::size_t grain, const Body& body) {
  const std::size_t chunks = (n + grain - 1) / grain;
  const auto threads = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  const std::size_t workers = std::min(chunks, threads);
  auto run = [&](const auto& chunk) {
    if (workers == 1) {
      for (std::size_t c = 0; c < chunks; ++c) chunk(c);
      return;
    }
    ChunkDealer dealer(chunks, workers);
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, workers, 1),
        [&](const tbb::blocked_range<std::size_t>& r) {
          for (std::size_t w = r.begin(); w != r.end(); ++w)
            dealer.work(w, [&](std::size_t c) { tbb::this_task_arena::isolate([&] { chunk(c); }); });
        },
        tbb::simple_partitioner());
  };
  if (WorkSpanRecorder* recorder = loop_recorder()) {
    LoopTimer timer(*recorder);
    run([&](std::size_t c) { timer.task([&] { body(c * grain, std::min(n, (c + 1) * grain)); }); });
    return;
  }
  run([&](std::size_t c) { body(c * grain, std::min(n, (c + 1) * grain)); });
}

/// body(begin, end) over chunks of about `grain` of [0, n) under `partitioner` (timed when the
/// stage is measured). Under tbb::simple_partitioner (chunks handed out one at a time) the
/// chunks are dealt out instead (dealt_for): a chunk then costs an atomic add where the
/// partitioner split the range into tasks, one spawn for each.
template <class Body, class Partitioner>
void chunked_for(std::size_t n, std::size_t grain, const Body& body, const Partitioner& partitioner) {
  if (n <= grain) {
    if (n) body(std::size_t(0), n);
    return;
  }
  if constexpr (std::is_same_v<Partitioner, tbb::simple_partitioner>) {
    dealt_for(n, grain, body);
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
      : recorder_(recorder), was_(tl_work_span), was_frame_(tl_frame), start_(Clock::now()) {
    tl_work_span = recorder;
    tl_frame = nullptr;  // a stage run from inside another's task (stolen) measures its own loops
  }
  ~StageClock() {
    tl_work_span = was_;
    tl_frame = was_frame_;
  }
  StageClock(const StageClock&) = delete;
  StageClock& operator=(const StageClock&) = delete;
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  /// The stage's work and span (zero when not measured), given its wall time as read from
  /// seconds(): the one read the stage's time and its work share, so that at one thread the
  /// work never exceeds that time.
  WorkSpan work_span(double wall) const { return recorder_ ? recorder_->finish(wall) : WorkSpan{}; }

 private:
  WorkSpanRecorder* recorder_;
  WorkSpanRecorder* was_;
  TaskFrame* was_frame_;
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
