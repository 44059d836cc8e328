// The engine's dealt loops (parallel/tbb_executor.h: dealt_for, behind every loop under
// tbb::simple_partitioner): every chunk of the grid [k grain, (k + 1) grain) runs exactly once,
// on any number of threads, measured or not; a chunk that throws ends the loop and its
// exception reaches the caller; a loop inside a chunk runs to its end (the chunk is isolated).
#include <gtest/gtest.h>

#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>

#include <atomic>
#include <memory>
#include <stdexcept>
#include <vector>

#include <mccd/parallel/tbb_executor.h>

using namespace mccd::detail;

namespace {

/// Runs dynamic_for(n, grain) and checks that its chunks are the grid's, each once.
void expect_grid_once(std::size_t n, std::size_t grain) {
  const std::size_t chunks = (n + grain - 1) / grain;
  auto seen = std::make_unique<std::atomic<int>[]>(chunks + 1);
  std::atomic<bool> off_grid{false};
  dynamic_for(n, grain, [&](std::size_t b, std::size_t e) {
    // a loop of one chunk runs body(0, n) itself; every other chunk is a cell of the grid
    if (b % grain != 0 || e != std::min(n, b + grain) || b >= e) off_grid = true;
    seen[b / grain].fetch_add(1);
  });
  EXPECT_FALSE(off_grid) << "n " << n << ", grain " << grain;
  for (std::size_t c = 0; c < chunks; ++c) ASSERT_EQ(seen[c].load(), 1) << "chunk " << c << " of n " << n;
}

}  // namespace

TEST(DealtFor, EveryChunkOfTheGridOnceOnAnyThreadCount) {
  for (int threads : {1, 2, 3, 4, 16}) {
    tbb::task_arena arena(threads);
    arena.execute([&] {
      for (std::size_t grain : {1, 7, 64})
        for (std::size_t n : {std::size_t(0), std::size_t(1), grain, grain + 1, 2 * grain, 1000 + grain, 4097 * grain})
          expect_grid_once(n, grain);
    });
  }
}

TEST(DealtFor, MeasuredLoopsRunEveryChunkOnceAndCountEachAsATask) {
  tbb::task_arena arena(4);
  arena.execute([] {
    WorkSpanRecorder recorder;
    {
      const StageClock clock(&recorder);
      expect_grid_once(10'000, 64);
      std::atomic<std::size_t> total{0};
      for_each_index(
          300, [&](std::size_t i) { total += i; }, tbb::simple_partitioner());
      EXPECT_EQ(total.load(), std::size_t(300 * 299 / 2));
      const mccd::WorkSpan ws = clock.work_span(clock.seconds());
      EXPECT_GT(ws.work, 0.0);
      EXPECT_LE(ws.span, ws.work * (1 + 1e-9) + 1e-12);
    }
  });
}

TEST(DealtFor, AThrowingChunkEndsTheLoopAndReachesTheCaller) {
  for (int threads : {1, 4}) {
    tbb::task_arena arena(threads);
    std::atomic<int> ran{0};
    arena.execute([&] {
      EXPECT_THROW(dynamic_for(1000, 1,
                               [&](std::size_t b, std::size_t) {
                                 ++ran;
                                 if (b == 10) throw std::runtime_error("chunk 10");
                               }),
                   std::runtime_error);
    });
    EXPECT_LE(ran.load(), 1000);
    // on one thread the chunks run in order and stop at the one that threw
    if (threads == 1) {
      EXPECT_EQ(ran.load(), 11);
    }
    // the arena is still usable afterwards, every chunk once
    arena.execute([] { expect_grid_once(5000, 3); });
  }
}

TEST(DealtFor, LoopsInsideChunksRunToTheirEnd) {
  tbb::task_arena arena(4);
  arena.execute([] {
    constexpr std::size_t kOuter = 64, kInner = 200;
    std::vector<std::atomic<int>> cells(kOuter * kInner);
    for_each_index(
        kOuter,
        [&](std::size_t i) {
          dynamic_for(kInner, 3, [&](std::size_t b, std::size_t e) {
            for (std::size_t j = b; j != e; ++j) cells[i * kInner + j].fetch_add(1);
          });
        },
        tbb::simple_partitioner());
    for (std::size_t k = 0; k < cells.size(); ++k) ASSERT_EQ(cells[k].load(), 1) << "cell " << k;
  });
}
