#pragma once
/// @file Internal: what a step computes, and the state its workers share for the simulator
/// queries (Scene::is_collision_free, earliest_impact, candidates). A full step reports every
/// contact; the queries let the workers stop or prune early:
///  - FirstContact: the first certified contact stops every worker (only "some contact"
///    matters); traversals check the flag at every node;
///  - Earliest: a running minimum of the times of impact found; a feature pair whose swept
///    volumes first overlap in a quarter of the step that starts at or after it is skipped
///    (it cannot have an earlier contact: a contact at time t lies in the pieces holding t);
///  - Candidates: feature pairs are collected after their volume tests, without the narrow
///    phase.
#include <atomic>
#include <bit>
#include <cstdint>
#include <limits>

namespace mccd::detail {

enum class StepKind : std::uint8_t { Full, FirstContact, Earliest, Candidates };

class QueryState {
 public:
  void reset(StepKind kind) {
    kind_ = kind;
    stop_.store(false, std::memory_order_relaxed);
    best_.store(std::bit_cast<std::uint64_t>(std::numeric_limits<double>::infinity()), std::memory_order_relaxed);
  }
  StepKind kind() const { return kind_; }
  /// Whether workers may stop now (a FirstContact query that found a contact).
  bool stopped() const { return kind_ == StepKind::FirstContact && stop_.load(std::memory_order_relaxed); }
  /// The earliest time of impact found so far (+inf when none).
  double best() const { return std::bit_cast<double>(best_.load(std::memory_order_relaxed)); }
  /// Records a contact found at `toi` in [0, 1].
  void found(double toi) {
    stop_.store(true, std::memory_order_relaxed);
    // Non-negative doubles order as their bit patterns: an integer minimum.
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(toi);
    std::uint64_t cur = best_.load(std::memory_order_relaxed);
    while (bits < cur && !best_.compare_exchange_weak(cur, bits, std::memory_order_relaxed)) {
    }
  }

 private:
  StepKind kind_ = StepKind::Full;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> best_{0};
};

}  // namespace mccd::detail
