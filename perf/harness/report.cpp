#include "harness/report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include <mccd/geometry/atomic_file.h>

namespace mccd::bench {

namespace {

std::string num(double v, int digits = 2) {
  if (!std::isfinite(v)) return "n/a";
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

// 1234567 -> "1.23 M", 12345 -> "12.3 K"
std::string count(double v) {
  if (!std::isfinite(v)) return "n/a";
  char b[64];
  if (v >= 1e6) std::snprintf(b, sizeof b, "%.3g M", v / 1e6);
  else if (v >= 1e4) std::snprintf(b, sizeof b, "%.3g K", v / 1e3);
  else std::snprintf(b, sizeof b, "%.0f", v);
  return b;
}

std::string percent_fewer(double before, double after) {
  return before > 0 && std::isfinite(after) ? num(100 * (1 - after / before), 1) + "%" : "n/a";
}

// "9.81x [9.52-10.3]": a paired speedup, its least and its most
std::string paired_text(double median, double least, double most) {
  if (!std::isfinite(median)) return "n/a";
  return num(median) + "x [" + num(least) + "-" + num(most) + "]";
}

std::string first_line_of(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (key.empty() || line.rfind(key, 0) == 0) return line;
  return "";
}

}  // namespace

std::string cpu_model() {
  const std::string line = first_line_of("/proc/cpuinfo", "model name");
  const auto colon = line.find(':');
  return colon == std::string::npos ? "unknown CPU" : line.substr(line.find_first_not_of(" \t", colon + 1));
}

std::string load_average() {
  std::istringstream in(first_line_of("/proc/loadavg", ""));
  std::string a, b, c;
  return in >> a >> b >> c ? a + " " + b + " " + c : "n/a";
}

std::string default_machine_name() {
  std::string words, out;
  for (char ch : cpu_model()) words += char(std::tolower(static_cast<unsigned char>(ch)));
  std::istringstream in(words);
  for (std::string w; in >> w;) {
    for (const char* drop : {"(r)", "(tm)"})
      for (std::size_t at; (at = w.find(drop)) != std::string::npos;) w.erase(at, std::string(drop).size());
    std::string clean;
    for (char ch : w)
      if (std::isalnum(static_cast<unsigned char>(ch)) || ch == '.') clean += ch;
    if (clean.empty() || clean == "processor" || clean == "cpu" || clean.find('@') != std::string::npos) continue;
    out += (out.empty() ? "" : "-") + clean;
  }
  const unsigned n = std::max(1u, std::thread::hardware_concurrency());
  return (out.empty() ? std::string("machine") : out) + "-" + std::to_string(n) + "t";
}

void write_runs_csv(const std::string& path, const std::vector<RunRecord>& runs) {
  std::ostringstream o;
  o << "scene,config,method,threads,run,steps,intervals,wall_ms,ms_per_frame,first_step_ms,update_ms,refit_ms,"
       "search_ms,self_ms,contacts_ms,engine_total_ms,volume_tests,feature_box_tests,vf_tests,ee_tests,vf_contacts,"
       "ee_contacts,contacts,leaf_pairs,adjacent_leaf_pairs,sprouted,invalidated,rebuilds,rebuild_front,"
       "rebuild_adjacent,max_front_size,max_front_bytes\n";
  o.precision(9);
  for (const RunRecord& r : runs) {
    const StepStats& s = r.sum;
    o << r.scene << ',' << r.config << ',' << to_string(r.method) << ',' << r.threads << ',' << r.run << ',' << r.steps << ','
      << r.intervals << ',' << r.wall_ms << ',' << r.wall_ms / std::max(1, r.intervals) << ',' << r.first_step_ms;
    for (double t : {s.t_update, s.t_refit, s.t_front, s.t_self, s.t_contacts, s.t_total}) o << ',' << 1e3 * t;
    for (std::uint64_t c : {s.volume_tests, s.feature_box_tests, s.vf_tests, s.ee_tests, s.vf_contacts, s.ee_contacts,
                            r.contacts, s.leaf_pairs, s.adjacent_leaf_pairs, s.sprouted, s.invalidated, r.rebuilds,
                            r.rebuild_front, r.rebuild_adjacent, r.max_front_size, r.max_front_bytes})
      o << ',' << c;
    o << '\n';
  }
  write_atomically(path, o.str());
}

std::string report_markdown(const MachineInfo& m, const std::vector<SceneSummary>& scenes,
                            const std::vector<VariantSummary>& variants) {
  std::ostringstream o;
  o << "# mccd benchmarks: " << m.name << "\n\n"
    << "Machine: " << m.cpu << ", " << m.hardware_threads << " hardware threads. Load average (1, 5, 15 min) "
    << m.load_before << " before the sweep, " << m.load_after << " after. " << m.date << ".\n\n"
    << "Command: `" << m.command << "`\n\n";
  if (!m.cores_before.empty() || !m.cores_after.empty()) {
    const Ceiling lo = speedup_ceiling(m.cores_before, m.hardware_threads),
                  hi = speedup_ceiling(m.cores_after, m.hardware_threads);
    char ceil[160];
    std::snprintf(ceil, sizeof ceil, "%.2fx-%.2fx before, %.2fx-%.2fx after", lo.from_fastest, lo.from_slowest,
                  hi.from_fastest, hi.from_slowest);
    o << "Each core alone, one thread pinned to it, against the fastest (compute / cache-bound): before the sweep "
      << core_rates_text(m.cores_before) << "; after " << core_rates_text(m.cores_after)
      << ". Unequal cores cap a speedup on all " << m.hardware_threads
      << " threads at the sum of their rates over the 1-thread run's core's: " << ceil
      << " (1-thread run on the fastest core - on the slowest).\n\n";
  }
  o
    << "Each variant (scene x method x threads) first runs once as a warm-up whose contacts are compared, step by step,\n"
    << "with the serial result (traverse, 1 thread); then " << m.repeats << " timed runs from a fresh scene. Times are\n"
    << "wall-clock ms per frame interval (all steps of a run over the frame intervals they cover): median [min-max].\n"
    << "Every variant runs with the library's defaults (SAH tree, 21 triangles per leaf, the leaf representative rule);\n"
    << "traverse and fbd also run once on 1 thread in the paper's configuration (its median tree, one triangle per\n"
    << "leaf, the canonical rule with its orphan set), checked the same way, for figures 7 and 9.\n\n";

  o << "## Scenes\n\n| scene | triangles | steps | frame intervals | what |\n| --- | --- | --- | --- | --- |\n";
  for (const SceneSummary& s : scenes)
    o << "| " << s.scene << " | " << s.triangles << " | " << s.steps << " | " << s.intervals << " | " << s.description << " |\n";

  o << "\n## Summary\n\nMethod " << (scenes.empty() ? "fbd" : to_string(scenes.front().method))
    << "; speedup = ms at 1 thread / ms at the most threads swept (medians); paired = the same run by run, each\n"
       "timed run over the 1-thread run of its round (median [min-max]), which a machine whose speed moves between\n"
       "rounds moves less; the model is Amdahl's law with the serial fraction s fitted to the measured thread counts\n"
       "(formula below).\n\n"
       "| scene | ms/frame, 1 thread | ms/frame, most threads | speedup | paired | serial fraction | model, 16 threads | "
       "volume tests/step: traverse -> fbd | fewer | paper's setting: fewer | paper's setting, front at rebuild: "
       "without -> with orphan set | shorter | elementary tests per contact | front memory |\n"
       "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const SceneSummary& s : scenes) {
    if (s.ms.empty()) continue;
    const double without = s.front_nodes + s.front_adjacent;
    o << "| " << s.scene << " | " << num(s.ms.front()) << " | " << num(s.ms.back()) << " (" << s.threads.back()
      << ") | " << num(s.ms.front() / s.ms.back()) << "x | " << paired_text(s.paired.back(), s.paired_min.back(),
      s.paired_max.back()) << " | " << num(s.serial[kStep], 3) << " | "
      << num(s.amdahl16[kStep], 1) << "x | " << count(s.volume_tests_traverse) << " -> " << count(s.volume_tests_method)
      << " | " << percent_fewer(s.volume_tests_traverse, s.volume_tests_method) << " | "
      << percent_fewer(s.paper_volume_traverse, s.paper_volume_fbd) << " (" << count(s.paper_volume_traverse) << " -> "
      << count(s.paper_volume_fbd) << ") | " << count(without) << " -> "
      << count(s.front_nodes) << " | " << percent_fewer(without, s.front_nodes) << " | "
      << num(s.contacts > 0 ? s.elementary_tests / s.contacts : NAN, 1) << " (" << count(s.elementary_tests) << " / "
      << count(s.contacts) << ") | " << num(s.front_mb, 1) << " MB |\n";
  }

  o << "\n## Every variant\n\n| scene | method | threads | ms/frame: median [min-max] | speedup over its 1 thread | "
       "paired by round | over traverse, 1 thread | fbd/phc time | volume tests/step | elementary tests/step | "
       "contacts/step |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const VariantSummary& v : variants) {
    if (v.config != "default") continue;
    double one = NAN, trav = NAN, phc = NAN, fbd = NAN;
    for (const VariantSummary& w : variants) {
      if (w.scene != v.scene || w.config != "default") continue;
      if (w.method == v.method && w.threads == 1) one = w.median_ms[kStep];
      if (w.method == Method::Traverse && w.threads == 1) trav = w.median_ms[kStep];
      if (w.threads == v.threads && w.method == Method::Phc) phc = w.median_ms[kStep];
      if (w.threads == v.threads && w.method == Method::Fbd) fbd = w.median_ms[kStep];
    }
    const double steps = std::max(1, v.counts.steps);
    o << "| " << v.scene << " | " << to_string(v.method) << " | " << v.threads << " | " << num(v.median_ms[kStep]) << " ["
      << num(v.min_ms) << "-" << num(v.max_ms) << "] | " << num(one / v.median_ms[kStep]) << "x | "
      << paired_text(v.paired_speedup, v.paired_min, v.paired_max) << " | "
      << num(trav / v.median_ms[kStep]) << "x | " << (v.method == Method::Fbd ? num(fbd / phc, 3) : "") << " | "
      << count(v.counts.sum.volume_tests / steps) << " | "
      << count((v.counts.sum.vf_tests + v.counts.sum.ee_tests) / steps) << " | " << count(v.counts.contacts / steps)
      << " |\n";
  }

  o << "\n## Stages\n\nms per frame of each stage (StepStats: update = volume update, refit, search = front tracking or\n"
       "traversal with its leaf pairs and elementary tests, self = the pairs no front node holds (each leaf's own\n"
       "pairs with the leaf rule, the orphan set with the canonical one; beside the search in the step's flow\n"
       "graph, sharing its threads), contacts = the join into the canonical order; search + self = the part of\n"
       "the step those two take together (the engine's time less update, refit and contacts); step = the whole\n"
       "step, wall clock), its serial fraction and the speedup Amdahl's law gives it on 16 threads. The search and\n"
       "the self stage alone get no fraction: each one's wall time spans the time the other holds the threads.\n\n"
       "| scene | method | stage |";
  std::vector<int> threads = scenes.empty() ? std::vector<int>{} : scenes.front().threads;
  for (int t : threads) o << " " << t << (t == 1 ? " thread" : " threads") << " |";
  o << " serial fraction | model, 16 threads |\n|";
  for (std::size_t i = 0; i < threads.size() + 5; ++i) o << " --- |";
  o << "\n";
  for (const SceneSummary& s : scenes)
    for (int st = 0; st < kStageCount; ++st) {
      o << "| " << s.scene << " | " << to_string(s.method) << " | " << stage_name(st) << " |";
      for (int t : threads) {
        double ms = NAN;
        for (const VariantSummary& v : variants)
          if (v.scene == s.scene && v.config == "default" && v.method == s.method && v.threads == t) ms = v.median_ms[st];
        o << " " << num(ms, 3) << " |";
      }
      if (stage_scales_alone(st))
        o << " " << num(s.serial[st], 3) << " | " << num(s.amdahl16[st], 1) << "x |\n";
      else
        o << " - | - |\n";
    }

  // Work and span: the prediction of every thread count from one measured 1-thread run.
  bool any_ws = false;
  for (const VariantSummary& v : variants) any_ws = any_ws || v.config == "work-span";
  if (any_ws) {
    o << "\n## Work and span\n\nEach method three times on 1 thread with its stages' work and span measured "
         "(every task of every\nparallel loop timed, nested loops and invokes at every depth; the search and the self "
         "stage as one branch;\neach stage's least work and span of the three; positions in: the step's positions "
         "checked and copied\nin before the stages; outside the stages: the least, of the three runs, of a run's wall "
         "time less its\nstages' work, counted as serial: what runs in no stage, and on one thread the loops' "
         "scheduling and\ntiming). "
         "Predicted ms/frame on P threads: the "
         "time outside the\nstages plus, per stage, span + (work - span) / P; beside it the measured median (error = "
         "predicted /\nmeasured - 1). Memory bandwidth and scheduling costs are not in the model. Last: the same prediction\n"
         "scaled to the measured 2-thread median (measured at 2 x predicted at P / predicted at 2): the instrumented\n"
         "runs are slower than the timed ones, and a lent machine's speed moves between runs.\n\n"
         "The work on 2 threads (the same three runs, when the sweep ran several threads) is beside it: a stage\nwhose work "
         "grows there spends what one thread does not (memory moved between cores, code that runs only\non several "
         "threads, waits inside tasks), which the prediction above does not see.\n\n"
         "| scene | method | stage | work ms/frame | span ms/frame | parallelism | work on 2 threads | 2 / 1 |\n"
         "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
    for (const VariantSummary& v : variants) {
      if (v.config != "work-span") continue;
      const StepStats& s = v.counts.sum;
      const double k = 1.0 / std::max(v.counts.intervals, 1);
      // the same scene and method measured on 2 threads, when it was
      const StepStats* two = nullptr;
      for (const VariantSummary& w : variants)
        if (w.config == "work-span-2" && w.scene == v.scene && w.method == v.method) two = &w.counts.sum;
      using Member = WorkSpan StepStats::*;
      const std::pair<const char*, Member> stages[] = {
          {"update", &StepStats::ws_update}, {"refit", &StepStats::ws_refit},
          {"search", &StepStats::ws_search}, {"self", &StepStats::ws_self},
          {"search + self", &StepStats::ws_branch}, {"join", &StepStats::ws_join},
          {"positions in", &StepStats::ws_input}};
      // what the prediction counts as serial (predicted_ms)
      const double outside = v.counts.outside_ms >= 0 ? v.counts.outside_ms / 1e3
                                                      : std::max(0.0, v.counts.wall_ms / 1e3 - s.staged_work());
      for (const auto& [name, member] : stages) {
        const WorkSpan& ws = s.*member;
        o << "| " << v.scene << " | " << to_string(v.method) << " | " << name << " | " << num(1e3 * ws.work * k, 3)
          << " | " << num(1e3 * ws.span * k, 3) << " | " << num(ws.span > 0 ? ws.work / ws.span : NAN, 1) << " | ";
        if (two)
          o << num(1e3 * ((*two).*member).work * k, 3) << " | "
            << num(ws.work > 0 ? ((*two).*member).work / ws.work : NAN, 2) << " |\n";
        else
          o << "- | - |\n";
      }
      o << "| " << v.scene << " | " << to_string(v.method) << " | outside the stages | " << num(1e3 * outside * k, 3)
        << " | " << num(1e3 * outside * k, 3) << " | 1.0 | - | - |\n";
    }
    o << "\n| scene | method | threads | predicted ms/frame | measured ms/frame | error | from 2 threads | error |\n"
         "| --- | --- | --- | --- | --- | --- | --- | --- |\n";
    for (const VariantSummary& v : variants) {
      if (v.config != "work-span") continue;
      std::vector<int> shown;
      for (const VariantSummary& w : variants)
        if (w.scene == v.scene && w.config == "default" && w.method == v.method) shown.push_back(w.threads);
      for (int t : {16}) if (std::find(shown.begin(), shown.end(), t) == shown.end()) shown.push_back(t);
      auto measured_at = [&](int t) {
        for (const VariantSummary& w : variants)
          if (w.scene == v.scene && w.config == "default" && w.method == v.method && w.threads == t)
            return w.median_ms[kStep];
        return double(NAN);
      };
      auto error = [](double p, double m) {
        return std::isnan(p) ? std::string("-")
               : std::isnan(m) ? std::string("(predicted only)")
                               : num(100 * (p / m - 1), 1) + "%";
      };
      const double two = measured_at(2);
      for (int t : shown) {
        const double p = predicted_ms(v.counts, t), measured = measured_at(t);
        const double q = std::isnan(two) ? NAN : predicted_from_ms(v.counts, t, 2, two);
        o << "| " << v.scene << " | " << to_string(v.method) << " | " << t << " | " << num(p, 2) << " | "
          << num(measured, 2) << " | " << error(p, measured) << " | " << (std::isnan(q) ? "-" : num(q, 2)) << " | "
          << error(q, measured) << " |\n";
      }
    }
  }

  o << "\n## How the serial fraction is estimated\n\n"
       "Amdahl's law: T(p) = T(1) (s + (1 - s)/p). With r_p = T(p)/T(1), the least-squares fit over the thread\n"
       "counts p > 1 is s = sum_p (r_p - 1/p)(1 - 1/p) / sum_p (1 - 1/p)^2, clamped to [0, 1]; with 1 and 2\n"
       "threads only, s = 2 T(2)/T(1) - 1. The modelled speedup on 16 threads is 1 / (s + (1 - s)/16). On a\n"
       "shared, loaded machine T(2) is inflated by other work, so s is an upper bound.\n\n"
       "## The paper, for comparison (Tang, Manocha, Tong 2010; 16-core Xeon X7350, 2.93 GHz)\n\n"
       "| scene | triangles | ms/frame, 16 cores (table 2) | serial [3] (table 2) | speedup, 8 / 16 cores (figs. 13-18) |\n"
       "| --- | --- | --- | --- | --- |\n"
       "| Princess | 40 K | 5.3 | 55 | 6.4x / 10.2x |\n"
       "| Flamenco | 49 K | 27 | 350 | 7.7x / 13x |\n"
       "| N-body | 34 K | 11.6 | 117 | 6.6x / 10.1x |\n"
       "| Cloth-ball | 92 K | 32.5 | 340 | 6.68x / 10.5x |\n"
       "| BART | 4 K | 20.4 | 212 | 6.6x / 10.4x |\n\n"
       "Table 1 (shares of a serial step [3]; Princess / Flamenco / N-body / Cloth-ball): BVH update 48 / 15 / 20 / 25%,\n"
       "BVTT traversal 39 / 39 / 37 / 45%, non-adjacent pair tests 12 / 45 / 43 / 30%, adjacent pairs below 0.4%.\n"
       "Front tracking: 37-47% fewer volume tests (fig. 7); the orphan set shortens the front by 20-40% (fig. 9);\n"
       "FBD takes 40-48% less time than PHC on 8-16 cores (fig. 12); the BART front holds about 17 MB (section 7.2).\n";
  return o.str();
}

void write_report(const std::string& path, const MachineInfo& machine, const std::vector<SceneSummary>& scenes,
                  const std::vector<VariantSummary>& variants) {
  write_atomically(path, report_markdown(machine, scenes, variants));
}

}  // namespace mccd::bench
