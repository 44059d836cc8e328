#include "run_table.h"

#include <algorithm>
#include <iterator>
#include <cmath>
#include <cstdio>
#include <string>

#include "progress.h"

namespace mccd::cli {

namespace {


std::string duration(double s) {
  char buf[32];
  if (s < 1)
    std::snprintf(buf, sizeof buf, "%.1f ms", 1e3 * s);
  else
    std::snprintf(buf, sizeof buf, "%.2f s", s);
  return buf;
}

}  // namespace

std::string impact_text(double t) {
  if (std::isinf(t)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", t);
  return buf;
}

StepAccumulator::PairKey StepAccumulator::key(const Contact& c) {
  // (kind, mesh_a, a) then (mesh_b, b): ordered as the contacts' canonical order
  return {std::uint64_t(c.kind == ContactKind::EdgeEdge) << 63 | std::uint64_t(c.mesh_a) << 32 | c.a,
          std::uint64_t(c.mesh_b) << 32 | c.b};
}

bool StepAccumulator::add(std::size_t step, std::size_t substep, const StepResult& r) {
  if (substep == 0) {
    row_ = StepRow{};
    row_.step = step;
    row_.stats.method = r.stats.method;
    pairs_.clear();
  }
  row_.stats += r.stats;
  row_.stats.front_size = r.stats.front_size;
  row_.stats.front_bytes = r.stats.front_bytes;
  if (!r.contacts.empty())
    row_.first = std::min(row_.first, double(step) + (double(substep) + r.earliest_toi) / substeps_);
  if (substeps_ == 1) {
    row_.vf = r.stats.vf_contacts;
    row_.ee = r.stats.ee_contacts;
    return true;
  }
  // Each sub-step's contacts come sorted (the canonical order), and so do their keys: merged
  // in linear time, each pair kept once.
  keys_.clear();
  keys_.reserve(r.contacts.size());
  for (const Contact& c : r.contacts) keys_.push_back(key(c));
  merged_.clear();
  merged_.reserve(pairs_.size() + keys_.size());
  std::merge(pairs_.begin(), pairs_.end(), keys_.begin(), keys_.end(), std::back_inserter(merged_));
  merged_.erase(std::unique(merged_.begin(), merged_.end()), merged_.end());
  pairs_.swap(merged_);
  if (int(substep) + 1 < substeps_) return false;
  // vertex-face pairs first (ContactKind order)
  row_.vf = std::size_t(std::count_if(pairs_.begin(), pairs_.end(), [](const PairKey& k) { return k.first >> 63 == 0; }));
  row_.ee = pairs_.size() - row_.vf;
  return true;
}

void RunTable::print_legend() const {
  if (!verbose_) return;
  std::printf(
      "columns: step k = frame k to k+1 (its sub-steps together); VF, EE = vertex-face and edge-edge pairs in\n"
      "  contact during the step; vol tests = bounding-volume overlap tests; VF tests, EE tests = elementary tests\n"
      "  run; front = BVTT front nodes after the step (fbd only); sprouted = front nodes added by sprouting;\n"
      "  invalid = front nodes whose volumes overlapped and were expanded; rebuilt = front rebuilt from the root;\n"
      "  orphans = orphan pairs (features of adjacent triangles) tested past their box test; first impact =\n"
      "  earliest time of impact in frame time (k + t, t in [0, 1]); time = computation time of the step\n");
}

void RunTable::print_header() const {
  std::printf("%6s %9s %9s", "step", "VF", "EE");
  if (verbose_)
    std::printf(" %12s %10s %10s %10s %9s %9s %7s %8s", "vol tests", "VF tests", "EE tests", "front", "sprouted",
                "invalid", "rebuilt", "orphans");
  std::printf(" %13s %10s\n", "first impact", "time");
}

void RunTable::print_row(const StepRow& r) const {
  std::printf("%6zu %9s %9s", r.step, grouped(r.vf).c_str(), grouped(r.ee).c_str());
  if (verbose_) {
    const StepStats& s = r.stats;
    std::printf(" %12s %10s %10s %10s %9s %9s %7s %8s", grouped(s.volume_tests).c_str(), grouped(s.vf_tests).c_str(),
                grouped(s.ee_tests).c_str(), grouped(s.front_size).c_str(), grouped(s.sprouted).c_str(),
                grouped(s.invalidated).c_str(), s.rebuilds ? "yes" : "-",
                grouped(s.orphan_vf_tested + s.orphan_ee_tested).c_str());
  }
  std::printf(" %13s %10s\n", impact_text(r.first).c_str(), duration(r.stats.t_total).c_str());
}

void RunTotals::add(const StepRow& r) {
  ++steps;
  vf += r.vf;
  ee += r.ee;
  if (r.vf + r.ee) ++steps_with_contacts;
  if (r.first < first) {
    first = r.first;
    first_step = r.step;
  }
  step_seconds += r.stats.t_total;
}

void print_summary(const RunTotals& t, std::size_t frames, const char* method, int threads, double wall) {
  const std::string span = "frames 0 to " + std::to_string(frames ? frames - 1 : 0);
  if (t.vf + t.ee == 0) {
    std::printf("no collision in %zu step%s (%s)\n", t.steps, t.steps == 1 ? "" : "s", span.c_str());
  } else {
    std::printf("%zu step%s (%s), %zu with contacts: %s contacts (%s vertex-face, %s edge-edge)\n", t.steps,
                t.steps == 1 ? "" : "s", span.c_str(), t.steps_with_contacts, grouped(t.vf + t.ee).c_str(), grouped(t.vf).c_str(),
                grouped(t.ee).c_str());
    std::printf("first impact at frame time %s (step %zu, frame %zu to %zu)\n", impact_text(t.first).c_str(),
                t.first_step, t.first_step, t.first_step + 1);
  }
  std::printf("time: %s in steps, %s per step; %s in all (method %s, %d thread%s)\n", duration(t.step_seconds).c_str(),
              duration(t.steps ? t.step_seconds / double(t.steps) : 0.0).c_str(), duration(wall).c_str(), method,
              threads, threads == 1 ? "" : "s");
}

}  // namespace mccd::cli
