#include "harness/summary.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

namespace mccd::bench {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

namespace {

const VariantSummary* find(const std::vector<VariantSummary>& vs, const std::string& scene, Method m, int threads,
                           const std::string& config = "default") {
  for (const VariantSummary& v : vs)
    if (v.scene == scene && v.config == config && v.method == m && v.threads == threads) return &v;
  return nullptr;
}
}  // namespace

const char* stage_name(int stage) {
  static const char* names[kStageCount] = {"update", "refit", "search", "self", "contacts", "search + self", "step"};
  return names[stage];
}

bool stage_scales_alone(int stage) { return stage != kSearch && stage != kOrphans; }

double stage_ms(const RunRecord& r, int stage) {
  const StepStats& s = r.sum;
  const double beside = s.t_total - s.t_update - s.t_refit - s.t_contacts;
  const double sec[kStageCount] = {s.t_update, s.t_refit,  s.t_front, s.t_self, s.t_contacts,
                                   beside,     1e-3 * r.wall_ms};
  return 1e3 * sec[stage] / std::max(1, r.intervals);
}

double serial_fraction(const std::vector<std::pair<int, double>>& points) {
  double base = kNaN, num = 0, den = 0;
  for (const auto& [p, t] : points)
    if (p == 1) base = t;
  if (!(base > 0)) return kNaN;
  for (const auto& [p, t] : points)
    if (p > 1) {
      const double x = 1 - 1.0 / p;
      num += (t / base - 1.0 / p) * x;
      den += x * x;
    }
  return den > 0 ? std::clamp(num / den, 0.0, 1.0) : kNaN;
}

double amdahl_speedup(double s, int threads) { return 1.0 / (s + (1 - s) / threads); }

double predicted_ms(const RunRecord& measured, int threads) {
  StepStats s = measured.sum;
  // the whole of every step, as the timed runs measure it: the stages and the time outside them
  s.t_total = measured.outside_ms >= 0 ? s.staged_work() + measured.outside_ms / 1e3 : measured.wall_ms / 1e3;
  return 1e3 * s.predicted_seconds(threads) / std::max(measured.intervals, 1);
}

double predicted_from_ms(const RunRecord& measured, int threads, int from, double measured_from_ms) {
  return measured_from_ms * predicted_ms(measured, threads) / predicted_ms(measured, from);
}

std::vector<VariantSummary> summarize(const std::vector<RunRecord>& runs) {
  std::vector<VariantSummary> out;
  std::map<std::tuple<std::string, std::string, int, int>, std::vector<const RunRecord*>> timed;
  for (const RunRecord& r : runs) {
    const auto key = std::make_tuple(r.scene, r.config, int(r.method), r.threads);
    if (!timed.count(key)) {
      VariantSummary v;
      v.scene = r.scene, v.config = r.config, v.method = r.method, v.threads = r.threads, v.counts = r;
      out.push_back(v);
      timed[key];
    }
    if (r.run > 0) timed[key].push_back(&r);
  }
  for (VariantSummary& v : out) {
    const auto& rs = timed[std::make_tuple(v.scene, v.config, int(v.method), v.threads)];
    v.runs = int(rs.size());
    // each timed run over the 1-thread run of its round
    std::vector<double> paired;
    const auto one = timed.find(std::make_tuple(v.scene, v.config, int(v.method), 1));
    if (one != timed.end())
      for (const RunRecord* r : rs)
        for (const RunRecord* o : one->second)
          if (o->run == r->run && r->wall_ms > 0) paired.push_back(o->wall_ms / r->wall_ms);
    v.paired_speedup = median(paired);
    v.paired_min = paired.empty() ? kNaN : *std::min_element(paired.begin(), paired.end());
    v.paired_max = paired.empty() ? kNaN : *std::max_element(paired.begin(), paired.end());
    for (int s = 0; s < kStageCount; ++s) {
      std::vector<double> ms;
      for (const RunRecord* r : rs) ms.push_back(stage_ms(*r, s));
      v.median_ms[s] = median(ms);
      if (s == kStep && !ms.empty()) {
        v.min_ms = *std::min_element(ms.begin(), ms.end());
        v.max_ms = *std::max_element(ms.begin(), ms.end());
      }
    }
  }
  return out;
}

SceneSummary summarize_scene(const Workload& w, const std::vector<VariantSummary>& variants) {
  SceneSummary s;
  s.scene = w.name, s.description = w.description, s.triangles = w.mesh.num_faces();
  s.steps = int(w.steps()), s.intervals = w.intervals;
  std::vector<const VariantSummary*> mine;
  for (const VariantSummary& v : variants)
    if (v.scene == w.name && v.config == "default") mine.push_back(&v);
  if (mine.empty()) return s;
  s.method = mine.front()->method;
  for (const VariantSummary* v : mine)
    if (v->method == Method::Fbd) s.method = Method::Fbd;
  for (const VariantSummary* v : mine)
    if (v->method == s.method) {
      s.threads.push_back(v->threads), s.ms.push_back(v->median_ms[kStep]);
      s.paired.push_back(v->paired_speedup), s.paired_min.push_back(v->paired_min);
      s.paired_max.push_back(v->paired_max);
    }
  for (int st = 0; st < kStageCount; ++st) {
    std::vector<std::pair<int, double>> points;
    for (const VariantSummary* v : mine)
      if (v->method == s.method) points.emplace_back(v->threads, v->median_ms[st]);
    s.serial[st] = serial_fraction(points);
    s.amdahl16[st] = amdahl_speedup(s.serial[st], 16);
  }
  const VariantSummary* base = find(variants, w.name, s.method, 1);
  const VariantSummary* trav = find(variants, w.name, Method::Traverse, 1);
  const VariantSummary* phc = find(variants, w.name, Method::Phc, 1);
  if (!base) base = mine.front();
  const RunRecord& c = base->counts;
  const double steps = std::max(1, c.steps);
  s.volume_tests_method = c.sum.volume_tests / steps;
  s.volume_tests_traverse = trav ? trav->counts.sum.volume_tests / steps : kNaN;
  s.phc_ms_1 = phc ? phc->median_ms[kStep] : kNaN;
  const VariantSummary* paper_fbd = find(variants, w.name, Method::Fbd, 1, "paper");
  const VariantSummary* paper_trav = find(variants, w.name, Method::Traverse, 1, "paper");
  s.paper_volume_fbd = paper_fbd ? paper_fbd->counts.sum.volume_tests / steps : kNaN;
  s.paper_volume_traverse = paper_trav ? paper_trav->counts.sum.volume_tests / steps : kNaN;
  const RunRecord* p = paper_fbd ? &paper_fbd->counts : nullptr;
  s.front_nodes = p && p->rebuilds ? double(p->rebuild_front) / p->rebuilds : kNaN;
  s.front_adjacent = p && p->rebuilds ? double(p->rebuild_adjacent) / p->rebuilds : kNaN;
  s.front_mb = 1e-6 * double(c.max_front_bytes);
  s.elementary_tests = (c.sum.vf_tests + c.sum.ee_tests) / steps;
  s.contacts = (c.sum.vf_contacts + c.sum.ee_contacts) / steps;
  return s;
}

}  // namespace mccd::bench
