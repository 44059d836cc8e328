#pragma once
/// @file Internal: front tracking in parallel (the paper's FBD, sections 4.3-4.5, 5). The front,
/// in BVH-node order, is cut into fixed blocks of consecutive nodes (cache-ordered: a block's
/// nodes share BVH nodes); a parallel_for hands the blocks to idle threads as they finish
/// (work stealing). Each block writes its own part of the next front, its own contacts (fed
/// to the buffer as one batch) and its own counters; a sprout past the block's budget of work
/// goes on in tasks of its own, appended to the block's part in order (parallel/phc.h). The
/// parts are joined in block order, so neither the front nor the contacts depend on the thread
/// count.
#include <algorithm>
#include <vector>

#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>

#include <mccd/core/front.h>
#include <mccd/parallel/contact_buffer.h>
#include <mccd/parallel/phc.h>
#include <mccd/parallel/tbb_executor.h>

namespace mccd::detail {

/// Front nodes per block: enough work to amortise a task, small enough that sprouting blocks
/// balance across threads and that small scenes get more blocks than kSerialBlocks (with
/// leaves of up to 21 triangles a front holds few nodes). Blocks are cache-ordered, so the
/// costly leaf pairs of a contact region fall into the same few blocks: the longest block is
/// a step's critical path on many threads, and shorter blocks shorten it.
inline constexpr std::size_t kFrontBlock = 64;
/// Fronts of at most this many blocks are tracked on the calling thread (block by block, as
/// in parallel): a parallel loop costs more in waking threads than it saves there (512 nodes).
inline constexpr std::size_t kSerialBlocks = 8;

/// Tracks every block of `front` into blocks[0, n) and returns n; the front itself is advanced
/// by the caller from those outputs (BvttFront::advance); sprouting is BvttFront::track. What a
/// block's sprouts leave past its budget of work (`task_work`, kTaskWork) is traversed apart,
/// in parallel, and appended to the block's output (traverse_apart; all of it sprouted).
/// `readonly` (the simulator queries): the same tests without recording a next front
/// (BvttFront::track_readonly).
template <class Bvtt>
std::size_t track_front(const Bvtt& bvtt, const BvttFront& front, WorkerOutputs& blocks,
                        ContactBuffer& contacts, bool readonly = false, std::size_t task_work = kTaskWork) {
  const LargeVector<NodePair>& nodes = front.nodes();
  const std::size_t n = (nodes.size() + kFrontBlock - 1) / kFrontBlock;
  if (blocks.size() < n) blocks.resize(n);
  const bool serial = n <= kSerialBlocks;
  const std::size_t budget = serial ? static_cast<std::size_t>(-1) : task_work;
  // The next leaf pairs' data is read ahead only where the arena has several threads: on one
  // thread that was measured slower (perf/results/history.md, 2026-11-27).
  const bool touch_ahead = tbb::this_task_arena::max_concurrency() > 1;
  auto run = [&](std::size_t b) {
    WorkerOutput& o = blocks[b];
    o.clear();
    const std::size_t lo = b * kFrontBlock, hi = std::min(nodes.size(), lo + kFrontBlock);
    if (readonly)
      BvttFront::track_readonly(bvtt, nodes.data() + lo, nodes.data() + hi, o, budget);
    else
      BvttFront::track(bvtt, nodes.data() + lo, nodes.data() + hi, o, budget, touch_ahead);
    if (!o.left.empty()) {
      const std::size_t before = o.front.size();
      if (readonly)
        traverse_apart<false>(bvtt, o.left, o, contacts, task_work);
      else
        traverse_apart<true>(bvtt, o.left, o, contacts, task_work);
      o.stats.sprouted += o.front.size() - before;
      o.left.clear();
    }
    flush(o, contacts);
  };
  if (serial) {
    for (std::size_t b = 0; b < n; ++b) run(b);  // the same blocks, without waking a thread
  } else {
    for_each_index(n, run, tbb::simple_partitioner());
  }
  return n;
}

}  // namespace mccd::detail
