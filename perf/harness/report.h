#pragma once
/// @file The sweep's written results: a CSV with one row per run, and a Markdown report with
/// the per-scene summary, every variant, the stages with their serial fractions, and the
/// paper's own figures beside them.
#include <string>
#include <vector>

#include "harness/cores.h"
#include "harness/summary.h"

namespace mccd::bench {

/// Where and how the sweep ran, for the report's header.
struct MachineInfo {
  std::string name;         ///< the results folder's name
  std::string cpu;          ///< model name
  int hardware_threads = 0;
  std::string load_before, load_after;  ///< /proc/loadavg's three averages
  std::string date, command;
  int repeats = 0;
  /// Each core alone before and after the sweep (time_cores_alone(); empty: not measured).
  std::vector<CoreRate> cores_before, cores_after;
};

/// The CPU model name (/proc/cpuinfo), or "unknown CPU".
std::string cpu_model();
/// The 1, 5 and 15 minute load averages ("0.52 0.61 0.40"), or "n/a".
std::string load_average();
/// A folder name for this machine: the CPU model in lower case with its trademarks and
/// "processor"/"cpu" dropped, then the hardware thread count ("intel-xeon-2t").
std::string default_machine_name();

/// Every run, one row each (the warm-up has run = 0). Written atomically.
void write_runs_csv(const std::string& path, const std::vector<RunRecord>& runs);
/// The Markdown report. Written atomically.
void write_report(const std::string& path, const MachineInfo& machine, const std::vector<SceneSummary>& scenes,
                  const std::vector<VariantSummary>& variants);
/// The report's text (also printed by bench_core).
std::string report_markdown(const MachineInfo& machine, const std::vector<SceneSummary>& scenes,
                            const std::vector<VariantSummary>& variants);

}  // namespace mccd::bench
