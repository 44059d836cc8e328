#pragma once
/// @file What a step did: one counters type, filled by every stage and worker and added up
/// field by field in one place (operator+=).
#include <cstdint>

#include <mccd/core/options.h>
#include <mccd/geometry/ccd.h>

namespace mccd {

/// The work and span of a stage, in seconds (SceneOptions::work_span): work, the time its
/// threads spent on it (its serial parts plus every task of its parallel loops); span, its
/// serial parts plus the longest task of each parallel loop. Measured on one thread, they
/// predict its time on P threads as span + (work - span) / P (what a greedy scheduler
/// reaches, memory bandwidth and scheduling costs aside).
struct WorkSpan {
  double work = 0, span = 0;
  double predict(double threads) const { return span + (work - span) / threads; }
  WorkSpan& operator+=(const WorkSpan& o) {
    work += o.work;
    span += o.span;
    return *this;
  }
};

/// Counts are exact and independent of the thread count; times are wall-clock seconds.
struct StepStats {
  Method method = Method::Fbd;
  std::uint64_t updated_vertices = 0;   ///< vertices whose swept volumes were updated (static: none)
  std::uint64_t refit_nodes = 0;        ///< BVH nodes refitted (a static mesh's: none)
  std::uint64_t volume_tests = 0;       ///< bounding-volume overlap tests of BVH node pairs
  /// Volume tests of triangle pairs inside BVH leaf pairs of several triangles (and inside one
  /// such leaf); 0 with one triangle per leaf, where the leaf test is the triangle test.
  std::uint64_t triangle_tests = 0;
  std::uint64_t feature_box_tests = 0;  ///< feature-pair swept-volume tests before elementary tests
  /// Feature pairs past their volume tests that the coplanarity filter removed before the
  /// elementary test (geometry/ccd_filter.h). Where the pairs' own quarter volumes are tested
  /// after the filter (SceneOptions::volume_order), also pairs the filter removed whose own
  /// volumes would not have met.
  std::uint64_t vf_filtered = 0, ee_filtered = 0;
  std::uint64_t vf_tests = 0;           ///< vertex-face elementary tests run
  std::uint64_t ee_tests = 0;           ///< edge-edge elementary tests run
  /// Per-stage counts inside the elementary tests (queries, culled by the swept box and by
  /// the coplanarity filter, root isolation, fallbacks, hits).
  CcdCounters vf_ccd, ee_ccd;
  std::uint64_t vf_contacts = 0;
  std::uint64_t ee_contacts = 0;
  /// Leaf rule: BVH leaf pairs that met in some quarter of the step; canonical rule:
  /// non-adjacent triangle pairs whose volumes overlapped.
  std::uint64_t leaf_pairs = 0;
  /// Canonical rule: leaf pairs the traversal reached and skipped because every triangle pair
  /// in them is adjacent (their features are the orphan set's); without the orphan set they
  /// would be front nodes (paper equation 5, B_a). 0 under the leaf rule.
  std::uint64_t adjacent_leaf_pairs = 0;
  /// Leaf rule: leaf pairs and single leaves skipped because every corner of their leaves has
  /// the previous full step's start and end positions and they found nothing then (parts at
  /// rest; core/unchanged_leaves.h). Not in leaf_pairs.
  std::uint64_t repeated_leaf_pairs = 0;
  /// Leaf rule: BVH nodes certified this step to hold no self-collision (their patch is a
  /// disk whose projection along an axis stays one-to-one; core/self_culling.h), each covering
  /// its subtree.
  std::uint64_t culled_patches = 0;
  /// BVTT nodes skipped because a certified patch holds both their sides: self nodes, front
  /// nodes and single leaves. Not in leaf_pairs nor volume_tests.
  std::uint64_t culled_nodes = 0;
  std::uint64_t sprouted = 0;           ///< front nodes inserted by sprouting this step (S)
  std::uint64_t invalidated = 0;        ///< front nodes that overlapped and were expanded (B)
  std::uint64_t rebuilds = 0;           ///< 1 when the front was built from the root this step
  std::uint64_t orphan_vf_tested = 0;   ///< orphan VF pairs whose volumes overlapped and were tested
  std::uint64_t orphan_ee_tested = 0;
  std::uint64_t front_size = 0;         ///< front nodes after the step (fbd only)
  std::uint64_t front_bytes = 0;        ///< bytes held by the front buffers (fbd only)
  /// Stage times: volume update, refit (with the self-collision certificates), candidate search
  /// with leaf pairs and elementary tests (front tracking, traversal or brute force), the self
  /// stage (t_self: the pairs no front node holds, concurrent with the search: each leaf's
  /// own pairs under the leaf rule, the orphan set and the pairs inside leaves under the
  /// canonical rule), the join of contacts into the canonical order, and the whole step.
  double t_update = 0, t_refit = 0, t_front = 0, t_self = 0, t_contacts = 0, t_total = 0;
  /// With SceneOptions::work_span: each stage's work and span (WorkSpan); `branch` is the
  /// search and the self stage together (their spans add when they run one after the other,
  /// the longer counts when they run beside each other in the flow graph). Zero otherwise.
  WorkSpan ws_update, ws_refit, ws_search, ws_self, ws_branch, ws_join;
  /// With SceneOptions::work_span: the step's positions checked and copied in before the
  /// stages (parallel chunks; part of t_total, in no stage's time).
  WorkSpan ws_input;
  /// The work measured in the stages and the input (the sum of their WorkSpan::work).
  double staged_work() const;
  /// The step's predicted seconds on `threads` threads from the work and span measured (best
  /// from one thread): every stage's prediction and the input's plus the time outside them
  /// (t_total less staged_work(): serial).
  double predicted_seconds(double threads) const;

  /// Adds every count and time of `o` (the method is kept).
  StepStats& operator+=(const StepStats& o);
};

}  // namespace mccd
