#pragma once
/// @file Internal: front tracking in parallel (the paper's FBD, sections 4.3-4.5, 5). The front,
/// in BVH-node order, is cut into blocks of consecutive nodes (cache-ordered: a block's nodes
/// share BVH nodes; of about equal work by the last step's counts, BvttFront::cuts()); a
/// parallel_for hands the blocks to idle threads as they finish (work stealing). Each block
/// writes its own part of the next front, its own contacts (fed to the buffer as one batch)
/// and its own counters; a sprout past the block's budget of work
/// goes on in tasks of its own, appended to the block's part in order (parallel/phc.h). The
/// parts are joined in block order, so neither the front nor the contacts depend on the thread
/// count.
#include <algorithm>
#include <vector>

#include <oneapi/tbb/partitioner.h>

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
/// A front too small for kMinFrontBlocks blocks of kFrontBlock nodes gets smaller blocks, down
/// to kLeastFrontBlock nodes (BvttFront::block_size): a small scene's front (a few thousand
/// nodes) still gives every one of 16 threads several blocks.
inline constexpr std::size_t kMinFrontBlocks = 128, kLeastFrontBlock = 16;
/// Fronts of at most this many blocks of kFrontBlock nodes are tracked on the calling thread
/// (block by block, as in parallel): a parallel loop costs more in waking threads than it saves
/// there.
inline constexpr std::size_t kSerialBlocks = 8;

/// Adds the counts of units[0, n) to `stats`: chunks of units summed in parallel, then the
/// chunks' sums in order (a serial pass over thousands of units' counts was a long serial part
/// of a step that built its front from the root). Integer counts: the same sums in any order.
inline void add_counts(const WorkerOutputs& units, std::size_t n, StepStats& stats) {
  constexpr std::size_t kChunk = 64;
  if (n <= 2 * kChunk) {
    for (std::size_t i = 0; i < n; ++i) stats += units[i].stats;
    return;
  }
  std::vector<StepStats> sums((n + kChunk - 1) / kChunk);
  for_each_index(
      sums.size(),
      [&](std::size_t c) {
        for (std::size_t i = c * kChunk; i < std::min(n, (c + 1) * kChunk); ++i) sums[c] += units[i].stats;
      },
      tbb::simple_partitioner());
  for (const StepStats& s : sums) stats += s;
}

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
  // The front's cuts (blocks of about equal work, from the last step's counts) where it has
  // them, else fixed blocks (BvttFront::block_size).
  const std::vector<std::uint32_t>& cuts = front.cuts();
  const bool cut = cuts.size() >= 2 && cuts.back() == nodes.size();
  const std::size_t fixed = front.block_size(nodes.size());
  const std::size_t n = cut ? cuts.size() - 1 : (nodes.size() + fixed - 1) / fixed;
  if (blocks.size() < n) blocks.resize(n);
  const bool serial = nodes.size() <= kSerialBlocks * kFrontBlock;
  const std::size_t budget = serial ? static_cast<std::size_t>(-1) : task_work;
  auto run = [&](std::size_t b) {
    WorkerOutput& o = blocks[b];
    o.clear();
    const std::size_t lo = cut ? cuts[b] : b * fixed;
    const std::size_t hi = cut ? cuts[b + 1] : std::min(nodes.size(), lo + fixed);
    if (readonly)
      BvttFront::track_readonly(bvtt, nodes.data() + lo, nodes.data() + hi, o, budget);
    else
      BvttFront::track(bvtt, nodes.data() + lo, nodes.data() + hi, o, budget);
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
