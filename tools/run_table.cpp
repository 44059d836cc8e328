#include "run_table.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <string>

#include <mccd/geometry/large_allocator.h>

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

FrameNames::FrameNames(const std::vector<std::string>& files) {
  for (const std::string& f : files) names_.push_back(std::filesystem::path(f).filename().string());
}

std::string FrameNames::frame(std::size_t i) const {
  return i < names_.size() ? names_[i] : "frame " + std::to_string(i);
}

std::string FrameNames::frames(std::size_t a, std::size_t b) const {
  if (named()) return frame(a) + " to " + frame(b);
  return "frames " + std::to_string(a) + " to " + std::to_string(b);
}

std::string FrameNames::step(std::size_t k) const {
  if (named()) return frames(k, k + 1);
  return "frame " + std::to_string(k) + " to " + std::to_string(k + 1);
}

std::string FrameNames::key(std::size_t frames) const {
  if (!named() || frames == 0) return "";
  std::string out;
  auto add = [&](std::size_t i) {
    out += (out.empty() ? "" : ", ") + std::string("frame ") + std::to_string(i) + " = " + frame(i);
  };
  add(0);
  if (frames > 1) add(1);
  if (frames > 3) out += ", ...";
  if (frames > 2) add(frames - 1);
  return out;
}

void StepAccumulator::merge_last_two() {
  const std::size_t k = runs_.size();  // k - 1 runs
  const PairKey *a = keys_.data() + runs_[k - 3], *ae = keys_.data() + runs_[k - 2];
  const PairKey *b = ae, *be = keys_.data() + runs_[k - 1];
  scratch_.resize(std::size_t(be - a));
  PairKey* out = scratch_.data();
  while (a != ae && b != be) {
    const bool take_b = *b < *a;
    const bool both = !take_b && !(*a < *b);
    *out++ = take_b ? *b : *a;
    a += !take_b;
    b += take_b | both;
  }
  out = std::copy(b, be, std::copy(a, ae, out));
  const std::size_t begin = runs_[k - 3], merged = std::size_t(out - scratch_.data());
  std::copy(scratch_.data(), out, keys_.begin() + std::ptrdiff_t(begin));
  keys_.resize(begin + merged);
  runs_.pop_back();
  runs_.back() = keys_.size();
  levels_.pop_back();
  ++levels_.back();
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
    keys_.clear();
    runs_.assign(1, 0);
    levels_.clear();
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
  // Each sub-step's contacts come sorted (the canonical order), and so do their keys: a run
  // of their own, merged with the runs before as a binary counter carries (log2 K passes over
  // the step's pairs in all, most of them beside the sub-steps that follow).
  const std::size_t at = keys_.size(), need = at + r.contacts.size();
  if (need > keys_.capacity()) {
    // Room for the step's other sub-steps at this one's rate, in one array (of megabytes: in
    // huge pages where the system gives them, LargeAllocator).
    mccd::detail::LargeVector<PairKey> grown;
    const std::size_t rest = std::size_t(substeps_) - substep - 1;
    grown.reserve(std::max(need + rest * r.contacts.size(), 2 * keys_.capacity()));
    grown.assign(keys_.begin(), keys_.end());
    keys_.swap(grown);
  }
  keys_.resize(need);
  std::transform(r.contacts.begin(), r.contacts.end(), keys_.begin() + std::ptrdiff_t(at), key);
  runs_.push_back(keys_.size());
  levels_.push_back(0);
  while (levels_.size() >= 2 && levels_[levels_.size() - 1] == levels_[levels_.size() - 2]) merge_last_two();
  if (int(substep) + 1 < substeps_) return false;
  while (levels_.size() >= 2) merge_last_two();
  const std::size_t n = keys_.size();
  // vertex-face pairs first (ContactKind order)
  const auto ee = std::partition_point(keys_.begin(), keys_.begin() + std::ptrdiff_t(n),
                                       [](const PairKey& k) { return k.first >> 63 == 0; });
  row_.vf = std::size_t(ee - keys_.begin());
  row_.ee = n - row_.vf;
  return true;
}

void RunTable::print_legend(const FrameNames& names, std::size_t frames) const {
  if (names.named()) std::printf("frames: %s\n", names.key(frames).c_str());
  if (!verbose_) {
    std::printf("step k = frame k to k+1; first impact = frame time k + t, t in [0, 1] of the step\n");
    return;
  }
  std::printf(
      "columns: step k = frame k to k+1 (its sub-steps together); VF, EE = vertex-face and edge-edge pairs in\n"
      "  contact during the step; vol tests = bounding-volume overlap tests; VF tests, EE tests = elementary tests\n"
      "  run; front = BVTT front nodes after the step (fbd only); sprouted = front nodes added by sprouting;\n"
      "  invalid = front nodes whose volumes overlapped and were expanded; rebuilt = front rebuilt from the root;\n"
      "  orphans = orphan pairs (features of adjacent triangles) tested past their box test; first impact =\n"
      "  earliest time of impact in frame time (k + t, t in [0, 1] of the step; a t below 1e-3 in scientific\n"
      "  notation, as in 3 + 7.49e-6); time = computation time of the step\n");
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

void print_summary(const RunTotals& t, const FrameNames& names, const char* method, int threads, double wall,
                   const RunStop* stop) {
  if (stop)
    std::printf("run stopped at step %zu (%s), %zu of %zu step%s finished: %s\n", stop->step,
                names.step(stop->step).c_str(), t.steps, stop->steps, stop->steps == 1 ? "" : "s", stop->why.c_str());
  const std::string count = std::to_string(t.steps) + (stop ? " finished step" : " step") + (t.steps == 1 ? "" : "s");
  const std::string span = names.frames(0, t.steps);
  if (stop && t.steps == 0) {
    std::printf("no step finished\n");
  } else if (t.vf + t.ee == 0) {
    std::printf("no collision in %s%s (%s)\n", stop ? "the " : "", count.c_str(), span.c_str());
  } else {
    std::printf("%s (%s), %zu with contacts: %s contacts (%s vertex-face, %s edge-edge)\n", count.c_str(), span.c_str(),
                t.steps_with_contacts, grouped(t.vf + t.ee).c_str(), grouped(t.vf).c_str(), grouped(t.ee).c_str());
    std::printf("first impact at frame time %s (step %zu: %s)\n", impact_text(t.first).c_str(), t.first_step,
                names.step(t.first_step).c_str());
  }
  if (t.steps == 0)
    std::printf("time: %s in all (method %s, %d thread%s)\n", duration(wall).c_str(), method, threads,
                threads == 1 ? "" : "s");
  else
    std::printf("time: %s in steps, %s per step; %s in all (method %s, %d thread%s)\n", duration(t.step_seconds).c_str(),
                duration(t.step_seconds / double(t.steps)).c_str(), duration(wall).c_str(), method, threads,
                threads == 1 ? "" : "s");
}

}  // namespace mccd::cli
