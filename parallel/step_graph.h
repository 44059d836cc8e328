#pragma once
/// @file Internal: the oneTBB flow graph of one step, built once per scene and reused by every
/// step:
///
///   update -> refit -> search -> join
///                   \-> self ---/
///
/// update: positions to swept volumes; refit: the BVH's node volumes; search: the candidate
/// pairs of the method (front tracking, traversal, PHC or brute force) with their leaf pairs
/// and elementary tests; self: the pairs no BVTT pair node holds (each leaf's own pairs under
/// the leaf rule; the orphan set and the pairs inside leaves under the canonical rule), which
/// need only the refitted volumes, so they run beside the search; join: the contacts into the
/// canonical order. Each node calls the stage of its name; stages are parallel inside. The
/// graph runs in the arena of the thread that calls run() (a task_arena's execute() included),
/// re-attached at every run.
#include <functional>
#include <memory>

namespace mccd::detail {

class StepGraph {
 public:
  struct Stages {
    std::function<void()> update, refit, search, self, join;
  };
  explicit StepGraph(Stages stages);
  ~StepGraph();
  StepGraph(const StepGraph&) = delete;
  StepGraph& operator=(const StepGraph&) = delete;

  /// Runs one step through the graph and waits for it; rethrows what a stage threw.
  void run();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mccd::detail
