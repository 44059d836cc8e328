#pragma once
/// @file The sweep's plots, drawn by gnuplot (Debian's gnuplot-nox, pngcairo terminal), each
/// with a title, labelled axes and units: speedup against threads with the Amdahl model to 16
/// threads (paper figure 13), the stages' shares of a step (table 1), volume tests with and
/// without the front (figure 7), front length with and without the orphan set (figure 9), the
/// fbd/phc time ratio (figure 12), front memory (section 7.2) and elementary tests per contact.
#include <string>
#include <vector>

#include "harness/summary.h"

namespace mccd::bench {

/// Whether `gnuplot` runs and has the pngcairo terminal.
bool gnuplot_available();

/// Draws every plot into `dir` as PNG (each written to a temporary and renamed); returns
/// the file names. Throws mccd::Error naming the plot when gnuplot fails.
std::vector<std::string> draw_plots(const std::string& dir, const std::string& machine,
                                    const std::vector<SceneSummary>& scenes, const std::vector<VariantSummary>& variants);

}  // namespace mccd::bench
