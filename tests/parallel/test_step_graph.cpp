// The step's flow graph (parallel/step_graph.h): update, then refit, then search and self
// (both after refit, possibly together), then join, once each per run(), all done when run()
// returns; a graph runs again and again; what a stage throws comes out of run(), later
// stages do not run, and the graph runs normally afterwards. Stages record when they begin
// and end under a mutex; some sleep so that a wrong order has time to show on many threads.
#include <gtest/gtest.h>

#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <mccd/parallel/step_graph.h>

using mccd::detail::StepGraph;

namespace {

enum Stage { Update, Refit, Search, Self, Join, kStages };
const char* const kNames[] = {"update", "refit", "search", "self", "join"};

/// Records every stage's begin and end events in order; a stage may sleep, or throw.
struct Recorder {
  std::mutex m;
  std::vector<std::pair<int, bool>> events;  ///< (stage, end?)
  int throw_in = -1;                         ///< the stage that throws, -1: none
  std::atomic<int> running{0}, most_running{0};

  std::function<void()> stage(int s, int sleep_ms) {
    return [this, s, sleep_ms] {
      {
        std::lock_guard<std::mutex> lock(m);
        events.push_back({s, false});
      }
      const int now = ++running;
      int seen = most_running.load();
      while (now > seen && !most_running.compare_exchange_weak(seen, now)) {
      }
      if (sleep_ms) std::this_thread::sleep_for(std::chrono::milliseconds(sleep_ms));
      --running;
      if (throw_in == s) {
        std::lock_guard<std::mutex> lock(m);
        events.push_back({s, true});
        throw std::runtime_error(std::string("stage ") + kNames[s] + " failed");
      }
      std::lock_guard<std::mutex> lock(m);
      events.push_back({s, true});
    };
  }
  StepGraph::Stages stages() {
    // update and search sleep: a search that ran early, or a join that did not wait for it,
    // would show; self and refit sleep a little.
    return {stage(Update, 5), stage(Refit, 3), stage(Search, 10), stage(Self, 2), stage(Join, 0)};
  }
  /// Index of stage s's begin / end event (-1: absent).
  int at(int s, bool end) const {
    for (std::size_t i = 0; i < events.size(); ++i)
      if (events[i] == std::make_pair(s, end)) return static_cast<int>(i);
    return -1;
  }
  std::string trace() const {
    std::string t;
    for (auto [s, end] : events) t += std::string(end ? "/" : "") + kNames[s] + " ";
    return t;
  }
};

/// One run's events: every stage once, begun after its predecessors ended.
void expect_one_ordered_run(const Recorder& r) {
  ASSERT_EQ(r.events.size(), 2u * kStages) << r.trace();
  for (int s = 0; s < kStages; ++s) {
    ASSERT_NE(r.at(s, false), -1) << kNames[s] << " did not run: " << r.trace();
    ASSERT_LT(r.at(s, false), r.at(s, true)) << r.trace();
  }
  EXPECT_EQ(r.at(Update, false), 0) << "update first: " << r.trace();
  EXPECT_GT(r.at(Refit, false), r.at(Update, true)) << r.trace();
  EXPECT_GT(r.at(Search, false), r.at(Refit, true)) << r.trace();
  EXPECT_GT(r.at(Self, false), r.at(Refit, true)) << r.trace();
  EXPECT_GT(r.at(Join, false), r.at(Search, true)) << r.trace();
  EXPECT_GT(r.at(Join, false), r.at(Self, true)) << r.trace();
  EXPECT_EQ(r.at(Join, true), 2 * kStages - 1) << "join last: " << r.trace();
}

}  // namespace

TEST(StepGraph, RunsStagesInDependencyOrder) {
  Recorder r;
  StepGraph g(r.stages());
  g.run();
  expect_one_ordered_run(r);
}

TEST(StepGraph, RunsAgainAndAgain) {
  Recorder r;
  StepGraph g(r.stages());
  for (int i = 0; i < 5; ++i) {
    r.events.clear();
    g.run();
    SCOPED_TRACE("run " + std::to_string(i));
    expect_one_ordered_run(r);
  }
}

TEST(StepGraph, RunsInTheCallersArena) {
  // One thread: everything on it, in order; four: the same order constraints.
  for (int threads : {1, 4}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    tbb::task_arena arena(threads);
    Recorder r;
    StepGraph g(r.stages());
    arena.execute([&] { g.run(); });
    expect_one_ordered_run(r);
    if (threads == 1) {
      EXPECT_EQ(r.most_running.load(), 1);
    }
    r.events.clear();
    arena.execute([&] { g.run(); });
    expect_one_ordered_run(r);
  }
}

TEST(StepGraph, ExceptionPropagatesAndTheGraphRunsAgain) {
  for (int failing : {Update, Refit, Search, Self, Join}) {
    SCOPED_TRACE(std::string("throwing in ") + kNames[failing]);
    Recorder r;
    StepGraph g(r.stages());
    r.throw_in = failing;
    try {
      g.run();
      ADD_FAILURE() << "run() returned normally: " << r.trace();
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), std::string("stage ") + kNames[failing] + " failed");
    }
    // What comes after the failed stage never starts.
    EXPECT_EQ(r.at(Join, false) != -1, failing == Join) << r.trace();
    if (failing <= Refit) {
      EXPECT_EQ(r.at(Search, false), -1) << r.trace();
      EXPECT_EQ(r.at(Self, false), -1) << r.trace();
    }
    if (failing == Update) {
      EXPECT_EQ(r.at(Refit, false), -1) << r.trace();
    }
    // Then it runs normally, twice.
    r.throw_in = -1;
    for (int i = 0; i < 2; ++i) {
      r.events.clear();
      EXPECT_NO_THROW(g.run());
      expect_one_ordered_run(r);
    }
  }
}
