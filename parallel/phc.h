#pragma once
/// @file Internal: traversal from the root, serial and in parallel. The parallel one is the
/// paper's PHC baseline (section 3.3), also used to build the front: the top of the BVTT is
/// visited breadth-first, serially, round by round, until at least `min_tasks` nodes wait (or
/// none, or the top has done its budget of work, kTopWork); each waiting node's subtree is then traversed depth-first as one task, the tasks in
/// parallel, and a task past its budget of work hands the rest of its stack to tasks of its
/// own (traverse_split). Both splits depend only on the geometry, never on the thread count,
/// and every node is visited exactly as in a serial traversal: the same tests, stops and
/// contacts. PHC redoes this from the root every step; FBD (parallel/front_tracking.h) does it
/// once per rebuild.
#include <algorithm>
#include <cstddef>
#include <vector>

#include <oneapi/tbb/partitioner.h>

#include <mccd/parallel/contact_buffer.h>
#include <mccd/parallel/tbb_executor.h>

namespace mccd::detail {

/// Subtasks PHC splits the BVTT's top into (at least), from the BVH's size (never from the
/// thread count): a quarter of its nodes, from 256 to 4096. Enough that the heaviest subtree
/// pair does not decide the time on 16 threads, few enough that small scenes' tasks stay
/// worth a task.
inline std::size_t phc_tasks(std::size_t bvh_nodes) { return std::clamp<std::size_t>(bvh_nodes / 4, 256, 4096); }

/// Serial depth-first traversal from the root into `out` (the `traverse` method; with
/// `record`, a serial front build).
template <bool record, class Bvtt>
void traverse_serial(const Bvtt& bvtt, WorkerOutput& out, ContactBuffer& contacts) {
  out.clear();
  if (bvtt.bvh().size() == 0) return;
  out.stack.push_back({0, 0});
  bvtt.template traverse<record>(out);
  flush(out, contacts);
}

/// Work a task does (Bvtt::traverse's units: a node test 1, a leaf pair more) before it
/// hands the rest of its stack on: each node left there becomes a task of its own, the tasks
/// in parallel (traverse_split). A subtree pair full of contacts (a cloth folding onto itself)
/// is then spread over the threads instead of deciding the step's time as one task. A count,
/// never a time, so the split is the same on every run and thread count.
inline constexpr std::size_t kTaskWork = 256;

template <bool record, class Bvtt>
void traverse_split(const Bvtt& bvtt, WorkerOutput& out, ContactBuffer& contacts, std::size_t task_work);

/// Traverses each of `nodes` as a task of its own (traverse_split), the tasks in parallel,
/// and appends their outputs to `out` in the order of `nodes`: their stops to out.front, their
/// counts to out.stats (their contacts go to the buffer). The order depends on `nodes` alone,
/// never on which thread ran what.
template <bool record, class Bvtt>
void traverse_apart(const Bvtt& bvtt, const std::vector<NodePair>& nodes, WorkerOutput& out, ContactBuffer& contacts,
                    std::size_t task_work) {
  std::vector<WorkerOutput> parts(nodes.size());
  for_each_index(
      nodes.size(),
      [&](std::size_t i) {
        WorkerOutput& o = parts[i];
        o.stack.push_back(nodes[i]);
        traverse_split<record>(bvtt, o, contacts, task_work);
        flush(o, contacts);
      },
      tbb::simple_partitioner());
  for (const WorkerOutput& o : parts) {
    // their costly stops (Bvtt::traverse) move with them
    const std::size_t offset = out.front.size();
    for (const CostlyNode& c : o.costly) out.costly.push_back({static_cast<std::uint32_t>(offset + c.at), c.work});
    out.front.insert(out.front.end(), o.front.begin(), o.front.end());
    out.stats += o.stats;
  }
}

/// Depth-first traversal of out.stack for at most `task_work` units of work (at least 1);
/// what is left then is traversed apart (traverse_apart) and appended to `out`.
template <bool record, class Bvtt>
void traverse_split(const Bvtt& bvtt, WorkerOutput& out, ContactBuffer& contacts, std::size_t task_work) {
  bvtt.template traverse<record>(out, std::max<std::size_t>(task_work, 1));
  if (out.stack.empty()) return;
  std::vector<NodePair> left;
  left.swap(out.stack);
  traverse_apart<record>(bvtt, left, out, contacts, task_work);
}

/// Work (Bvtt::traverse's units) the serial top of PHC does at most, and one visit more:
/// where the BVTT stays narrow (a large cloth whose patches are certified free of
/// self-collision has few node pairs per level), expanding it until phc_tasks() nodes wait
/// was most of the traversal, on one thread. The tasks it leaves split themselves further
/// as they run (traverse_split), so a few hundred are enough to start with.
inline constexpr std::size_t kTopWork = 4 * kTaskWork;

/// PHC: outs[0] receives the serial top's work, outs[1 + i] task i's (with the parts it split
/// off, traverse_split); outs is resized to the number of tasks + 1. The top is expanded
/// breadth-first until `min_tasks` nodes wait, none is left, or it has done `top_work` units
/// of work (the nodes of the round it stopped in that it did not visit become tasks too).
template <bool record, class Bvtt>
void traverse_phc(const Bvtt& bvtt, WorkerOutputs& outs, ContactBuffer& contacts,
                  std::size_t min_tasks = 0, std::size_t task_work = kTaskWork, std::size_t top_work = kTopWork) {
  if (min_tasks == 0) min_tasks = phc_tasks(bvtt.bvh().size());
  if (outs.empty()) outs.resize(1);
  outs[0].clear();
  if (bvtt.bvh().size() == 0) {
    outs.resize(1);
    return;
  }
  std::vector<NodePair> tasks{{0, 0}}, next;
  std::size_t work = 0;
  while (!tasks.empty() && tasks.size() < min_tasks && work < top_work) {
    next.clear();
    std::size_t i = 0;
    for (; i < tasks.size() && work < top_work; ++i) {
      work += bvtt.work_of(tasks[i]);
      bvtt.template visit<record>(tasks[i], outs[0], next);
    }
    next.insert(next.end(), tasks.begin() + static_cast<std::ptrdiff_t>(i), tasks.end());
    tasks.swap(next);
  }
  bvtt.finish(outs[0]);
  flush(outs[0], contacts);
  // Grown with room to spare: the task count moves a little from build to build, and a
  // reallocation of the outputs, exact to the last count, moved them all serially each time.
  if (outs.capacity() < 1 + tasks.size()) outs.reserve((1 + tasks.size()) * 3 / 2);
  outs.resize(1 + tasks.size());
  for_each_index(
      tasks.size(),
      [&](std::size_t i) {
        WorkerOutput& o = outs[1 + i];
        o.clear();
        o.stack.push_back(tasks[i]);
        traverse_split<record>(bvtt, o, contacts, task_work);
        flush(o, contacts);
      },
      tbb::auto_partitioner());
}

}  // namespace mccd::detail
