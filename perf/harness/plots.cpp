#include "harness/plots.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <mccd/geometry/atomic_file.h>
#include <mccd/geometry/error.h>

namespace mccd::bench {

namespace fs = std::filesystem;

namespace {

// The paper's per-benchmark speedups on 8 and 16 cores (figures 14-18).
struct PaperSpeedup {
  const char* name;
  double at8, at16;
};
constexpr PaperSpeedup kPaper[] = {
    {"Princess", 6.4, 10.2}, {"Flamenco", 7.7, 13}, {"N-body", 6.6, 10.1}, {"Cloth-ball", 6.68, 10.5}, {"BART", 6.6, 10.4}};

std::string g(double v) {
  if (!std::isfinite(v)) return "NaN";
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

// One PNG: a gnuplot script with a common header, run once, its output renamed into place.
class Plot {
 public:
  Plot(const std::string& dir, const std::string& file, const std::string& title, const std::string& xlabel,
       const std::string& ylabel)
      : path_((fs::path(dir) / file).string()), tmp_(path_ + ".tmp" + std::to_string(::getpid()) + ".png") {
    s_ << "set terminal pngcairo size 1100,650 enhanced font 'DejaVu Sans,11'\n"
       << "set output '" << tmp_ << "'\n"
       << "set title \"" << title << "\" font ',13'\n"
       << "set xlabel \"" << xlabel << "\"\nset ylabel \"" << ylabel << "\"\n"
       << "set grid ytics lc rgb '#dddddd'\nset key outside right top\nset datafile missing 'NaN'\n";
  }
  std::ostringstream& script() { return s_; }
  /// A data block $name, one row per element of `rows`.
  void data(const std::string& name, const std::vector<std::string>& rows) {
    s_ << "$" << name << " << EOD\n";
    for (const std::string& r : rows) s_ << r << "\n";
    s_ << "EOD\n";
  }
  std::string draw() {
    const std::string script_path = path_ + ".tmp" + std::to_string(::getpid()) + ".gp";
    write_atomically(script_path, s_.str());
    const std::string cmd = "gnuplot '" + script_path + "' 2>&1";
    const int rc = std::system(cmd.c_str());
    fs::remove(script_path);
    std::error_code ec;
    if (rc != 0 || !fs::is_regular_file(tmp_)) {
      fs::remove(tmp_, ec);
      throw Error(path_ + ": gnuplot failed (status " + std::to_string(rc) + ")");
    }
    fs::rename(tmp_, path_, ec);
    if (ec) throw Error(path_ + ": " + ec.message());
    return fs::path(path_).filename().string();
  }

 private:
  std::string path_, tmp_;
  std::ostringstream s_;
};

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

std::string fewer_label(const std::string& scene, double before, double after) {
  if (!(before > 0) || !std::isfinite(after)) return quoted(scene);
  char b[96];
  const double change = std::round(-100 * (1 - after / before));
  std::snprintf(b, sizeof b, "\"%s (%+.0f%%)\"", scene.c_str(), change == 0 ? 0.0 : change);
  return b;
}

// A clustered bar chart of two series per scene on a log axis.
std::string two_bars(const std::string& dir, const std::string& file, const std::string& title, const std::string& ylabel,
                     const std::vector<std::string>& rows, const std::string& first, const std::string& second) {
  Plot p(dir, file, title, "scene (change)", ylabel);
  p.data("d", rows);
  p.script() << "set style data histograms\nset style histogram clustered gap 1\nset style fill solid 0.85 border -1\n"
             << "set logscale y\nset xtics rotate by -20\nset key inside top right\n"
             << "plot $d using 2:xtic(1) title \"" << first << "\" lc rgb '#4477aa', $d using 3 title \"" << second
             << "\" lc rgb '#ee6677'\n";
  return p.draw();
}

// One bar per scene.
std::string one_bar(const std::string& dir, const std::string& file, const std::string& title, const std::string& ylabel,
                    const std::vector<std::string>& rows, bool log, const std::string& colour) {
  Plot p(dir, file, title, "scene", ylabel);
  p.data("d", rows);
  p.script() << "set style data histograms\nset style fill solid 0.85 border -1\nset boxwidth 0.6\n"
             << (log ? "set logscale y\n" : "set yrange [0:*]\n") << "set xtics rotate by -20\nset key off\n"
             << "plot $d using 2:xtic(1) lc rgb '" << colour << "'\n";
  return p.draw();
}

}  // namespace

bool gnuplot_available() {
  return std::system("gnuplot -e \"set terminal pngcairo\" > /dev/null 2>&1") == 0;
}

std::vector<std::string> draw_plots(const std::string& dir, const std::string& machine,
                                    const std::vector<SceneSummary>& scenes, const std::vector<VariantSummary>& variants) {
  std::vector<std::string> files;
  const std::string on = " ({/=10 " + machine + "})";

  {  // figure 13: speedup against threads, measured and modelled
    Plot p(dir, "speedup.png", "Speedup of fbd against threads, Amdahl model to 16 (paper fig. 13)" + on,
           "threads", "speedup over 1 thread (x)");
    std::ostringstream plot;
    plot << "plot x with lines dt 3 lc rgb 'black' title 'linear'";
    int i = 0;
    for (const SceneSummary& s : scenes) {
      if (s.ms.empty()) continue;
      ++i;
      std::vector<std::string> rows;
      for (std::size_t k = 0; k < s.ms.size(); ++k) rows.push_back(std::to_string(s.threads[k]) + " " + g(s.ms.front() / s.ms[k]));
      p.data(std::string("m").append(std::to_string(i)), rows);
      const double sf = s.serial[kStep];
      plot << ", $m" << i << " with linespoints pt 7 ps 1.3 lw 2 lc " << i << " title '" << s.scene << "'";
      if (std::isfinite(sf))
        plot << ", 1/(" << g(sf) << "+(1-" << g(sf) << ")/x) with lines dt 2 lc " << i << " title sprintf('  model, s = %.3f', "
             << g(sf) << ")";
    }
    std::vector<std::string> paper;
    for (const PaperSpeedup& ps : kPaper) paper.push_back("8 " + g(ps.at8) + "\n16 " + g(ps.at16));
    p.data("paper", paper);
    plot << ", $paper with points pt 6 ps 1.5 lc rgb '#888888' title 'paper, 5 scenes, 16-core Xeon'\n";
    p.script() << "set xrange [1:16]\nset yrange [0:16]\nset xtics (1,2,4,6,8,10,12,14,16)\nset samples 61\n" << plot.str();
    files.push_back(p.draw());
  }
  {  // table 1: the stages' shares of a step at 1 thread
    Plot p(dir, "stages.png", "Share of each stage in a step at 1 thread (paper table 1)" + on, "scene, method",
           "share of the step's wall-clock time (%)");
    std::vector<std::string> rows;
    for (const SceneSummary& s : scenes)
      for (const VariantSummary& v : variants) {
        if (v.scene != s.scene || v.config != "default" || v.threads != 1 ||
            (v.method != Method::Traverse && v.method != Method::Fbd))
          continue;
        const double step = v.median_ms[kStep];
        std::string row = quoted(s.scene + " " + to_string(v.method));
        double rest = step;
        for (int st = kUpdate; st <= kContacts; ++st) row.append(" ").append(g(100 * v.median_ms[st] / step)), rest -= v.median_ms[st];
        rows.push_back(row + " " + g(std::max(0.0, 100 * rest / step)));
      }
    p.data("d", rows);
    p.script() << "set style data histograms\nset style histogram rowstacked\nset style fill solid 0.85 border -1\n"
               << "set boxwidth 0.7\nset yrange [0:110]\nset xtics rotate by -30\n"
               << "plot $d using 2:xtic(1) title 'volume update', $d using 3 title 'refit', $d using 4 title "
                  "'search + elementary tests', $d using 5 title 'own pairs of leaves / orphan set', $d using 6 title "
                  "'contact join', $d using 7 title 'other'\n";
    files.push_back(p.draw());
  }
  std::vector<std::string> volume, front, memory, elementary;
  for (const SceneSummary& s : scenes) {
    volume.push_back(fewer_label(s.scene, s.volume_tests_traverse, s.volume_tests_method) + " " +
                     g(s.volume_tests_traverse / 1e6) + " " + g(s.volume_tests_method / 1e6));
    const double without = s.front_nodes + s.front_adjacent;
    front.push_back(fewer_label(s.scene, without, s.front_nodes) + " " + g(without / 1e3) + " " + g(s.front_nodes / 1e3));
    memory.push_back(quoted(s.scene) + " " + g(s.front_mb));
    elementary.push_back(quoted(s.scene) + " " + g(s.contacts > 0 ? s.elementary_tests / s.contacts : NAN));
  }
  files.push_back(two_bars(dir, "volume_tests.png", "Bounding-volume tests per step with and without the front (paper fig. 7)" + on,
                           "volume tests per step (millions, log scale)", volume, "traverse (from the root)",
                           "fbd (front tracking)"));
  files.push_back(two_bars(dir, "front_length.png",
                           "Front length at a rebuild with and without the orphan set, paper's setting (fig. 9)" + on,
                           "front nodes (thousands, log scale)", front, "without: front + adjacent leaf pairs",
                           "with the orphan set: front"));
  {  // figure 12: fbd / phc
    Plot p(dir, "fbd_phc_ratio.png", "Time of fbd over time of phc (paper fig. 12)" + on, "threads",
           "fbd time / phc time (ratio)");
    std::ostringstream plot;
    plot << "plot 1 with lines dt 3 lc rgb 'black' title 'equal'";
    int i = 0;
    for (const SceneSummary& s : scenes) {
      std::vector<std::string> rows;
      for (int t : s.threads) {
        double fbd = NAN, phc = NAN;
        for (const VariantSummary& v : variants) {
          if (v.scene != s.scene || v.config != "default" || v.threads != t) continue;
          if (v.method == Method::Fbd) fbd = v.median_ms[kStep];
          if (v.method == Method::Phc) phc = v.median_ms[kStep];
        }
        rows.push_back(std::to_string(t) + " " + g(fbd / phc));
      }
      p.data(std::string("r").append(std::to_string(++i)), rows);
      plot << ", $r" << i << " with linespoints pt 7 ps 1.3 lw 2 lc " << i << " title '" << s.scene << "'";
    }
    p.data("paper", {"8 0.60", "16 0.52"});
    plot << ", $paper with points pt 6 ps 1.8 lc rgb '#888888' title 'paper, 8 and 16 cores'\n";
    p.script() << "set xrange [0.5:16.5]\nset yrange [0:*]\nset xtics (1,2,4,8,12,16)\n" << plot.str();
    files.push_back(p.draw());
  }
  memory.push_back("\"BART, paper (sec. 7.2)\" 17");
  files.push_back(one_bar(dir, "front_memory.png", "Memory held by the front, largest over the steps (paper section 7.2)" + on,
                          "front memory (MB, 10^6 bytes)", memory, false, "#228833"));
  files.push_back(one_bar(dir, "elementary_per_contact.png", "Elementary tests run per contact found (vf + ee)" + on,
                          "elementary tests per contact (log scale)", elementary, true, "#aa3377"));
  return files;
}

}  // namespace mccd::bench
