// `mccd queries`: runs the elementary CCD tests on benchmark query files and compares with
// their ground truth.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>

#include <CLI/App.hpp>

#include "command.h"
#include "options.h"
#include <mccd/geometry/ccd.h>
#include <mccd/geometry/error.h>
#include <mccd/geometry/query_io.h>

namespace {

namespace fs = std::filesystem;
using mccd::Error;

enum class Kind { VF, EE };

struct Stats {
  std::uint64_t queries = 0, positives = 0, with_truth = 0, reported = 0, fn = 0, fp = 0;
  double total_ns = 0, max_ns = 0;
};

// The kind of a file: --kind, else the nearest folder named vertex-face / edge-edge, else the
// file name (vf / ee in the name, as the Time-of-Impact files 227vf.csv, 227ee.csv).
bool kind_of(const fs::path& file, const std::string& forced, Kind& kind) {
  if (forced == "vf" || forced == "ee") {
    kind = forced == "vf" ? Kind::VF : Kind::EE;
    return true;
  }
  for (fs::path p = file.parent_path(); !p.empty() && p != p.root_path(); p = p.parent_path()) {
    const std::string name = p.filename().string();
    if (name == "vertex-face") return kind = Kind::VF, true;
    if (name == "edge-edge") return kind = Kind::EE, true;
    if (p == p.parent_path()) break;
  }
  const std::string stem = file.stem().string();
  const bool vf = stem.find("vf") != std::string::npos, ee = stem.find("ee") != std::string::npos;
  if (vf != ee) return kind = vf ? Kind::VF : Kind::EE, true;
  return false;
}

struct QueryOptions {
  std::vector<std::string> paths;
  std::string kind, truth;
  double min_distance = 0.0;
  int repeat = 5;
  bool verbose = false;
};

int queries(const QueryOptions& args) {
  const std::string forced = args.kind;
  mccd::CcdOptions options;
  options.min_distance = args.min_distance;
  const long repeat = args.repeat;
  const bool verbose = args.verbose;

  std::vector<fs::path> files;
  for (const std::string& p : args.paths) {
    if (fs::is_directory(p)) {
      std::vector<fs::path> found;
      for (const auto& entry : fs::recursive_directory_iterator(p))
        if (entry.is_regular_file() && entry.path().extension() == ".csv") found.push_back(entry.path());
      std::sort(found.begin(), found.end());
      files.insert(files.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(p)) {
      files.emplace_back(p);
    } else {
      throw Error(p + ": no such file or directory");
    }
  }
  if (files.empty()) throw Error(args.paths.front() + ": no .csv query files found");
  std::vector<bool> truth_json;
  bool have_json = false;
  if (!args.truth.empty()) {
    const std::string tp = args.truth;
    std::ifstream in(tp);
    if (!in) throw Error(tp + ": cannot open");
    nlohmann::json j;
    try {
      in >> j;
    } catch (const std::exception& e) {
      throw Error(tp + ": not valid JSON: " + e.what());
    }
    if (!j.is_array()) throw Error(tp + ": expected a JSON array of booleans");
    for (std::size_t i = 0; i < j.size(); ++i) {
      if (!j[i].is_boolean() && !j[i].is_number_integer())
        throw Error(tp + ": element " + std::to_string(i) + " is not a boolean");
      truth_json.push_back(j[i].is_boolean() ? j[i].get<bool>() : j[i].get<int>() != 0);
    }
    have_json = true;
  }

  // Read and check everything before running anything: kinds, files, and the truth count.
  std::vector<std::pair<Kind, std::vector<mccd::CcdQuery>>> sets;
  std::size_t without_truth = 0;
  for (const fs::path& file : files) {
    Kind kind;
    if (!kind_of(file, forced, kind))
      throw Error(file.string() + ": cannot tell vertex-face from edge-edge (use --kind vf|ee)");
    sets.emplace_back(kind, mccd::read_query_csv(file.string()));
    for (const auto& q : sets.back().second) without_truth += q.truth < 0;
  }
  if (have_json && truth_json.size() != without_truth)
    throw Error(args.truth + ": has " + std::to_string(truth_json.size()) + " entries for " +
                std::to_string(without_truth) + " queries without ground truth");

  std::map<Kind, Stats> stats;
  std::size_t json_index = 0;
  using clock = std::chrono::steady_clock;
  for (std::size_t fi = 0; fi < files.size(); ++fi) {
    const fs::path& file = files[fi];
    const Kind kind = sets[fi].first;
    const std::vector<mccd::CcdQuery>& qs = sets[fi].second;
    Stats& st = stats[kind];
    for (std::size_t qi = 0; qi < qs.size(); ++qi) {
      const mccd::CcdQuery& q = qs[qi];
      int truth = q.truth;
      if (truth < 0 && have_json) truth = truth_json[json_index++] ? 1 : 0;
      double toi = 1;
      bool hit = false;
      double best = HUGE_VAL;
      for (long r = 0; r < repeat; ++r) {
        const auto t0 = clock::now();
        hit = kind == Kind::VF ? mccd::vertex_face_ccd(q.points, toi, options)
                               : mccd::edge_edge_ccd(q.points, toi, options);
        const auto t1 = clock::now();
        best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count());
      }
      ++st.queries;
      st.total_ns += best;
      st.max_ns = std::max(st.max_ns, best);
      st.reported += hit;
      if (truth >= 0) {
        ++st.with_truth;
        st.positives += truth == 1;
        if (truth == 1 && !hit) {
          ++st.fn;
          std::cerr << "false negative: " << file.string() << " query " << qi << "\n";
        }
        if (truth == 0 && hit) {
          ++st.fp;
          if (verbose) std::cerr << "false positive: " << file.string() << " query " << qi << " toi " << toi << "\n";
        }
      }
    }
  }

  std::cout << "kind         queries  positives  reported  false-neg  false-pos   mean-ns    max-ns\n";
  bool any_fn = false;
  for (const auto& [kind, st] : stats) {
    any_fn = any_fn || st.fn > 0;
    std::cout << std::left << std::setw(11) << (kind == Kind::VF ? "vertex-face" : "edge-edge") << std::right
              << std::setw(9) << st.queries << std::setw(11) << st.positives << std::setw(10) << st.reported
              << std::setw(11) << st.fn << std::setw(11) << st.fp << std::setw(10) << std::fixed
              << std::setprecision(1) << (st.queries ? st.total_ns / static_cast<double>(st.queries) : 0.0)
              << std::setw(10) << st.max_ns << "\n";
    if (st.with_truth < st.queries)
      std::cout << "  (" << st.queries - st.with_truth << " queries without ground truth)\n";
  }
  std::cout << "time per query: the fastest of " << repeat << " runs, steady_clock around one call\n";
  return any_fn ? 1 : 0;
}

const mccd::cli::Command reg(
    "queries", "run the elementary CCD tests on benchmark query files (CSV) and compare with their ground truth", 50,
    [](CLI::App& app) -> mccd::cli::Runner {
      auto o = std::make_shared<QueryOptions>();
      app.add_option("PATH", o->paths,
                     "query CSV files (8 rows per query, 7 columns: x, y, z as numerator/denominator, truth) "
                     "or folders, searched recursively for .csv files")
          ->required()
          ->type_name("PATH");
      app.add_option("--kind", o->kind,
                     "vf or ee for every file; default: from a folder named vertex-face / edge-edge, else from "
                     "vf / ee in the file name")
          ->type_name("KIND")
          ->check(CLI::IsMember({"vf", "ee"}));
      app.add_option("--truth", o->truth,
                     "a JSON array of booleans, the ground truth of the queries whose CSV truth column is "
                     "missing, in file order")
          ->type_name("FILE.json");
      mccd::cli::add_min_distance_option(app, o->min_distance);
      app.add_option("--repeat", o->repeat, "time each query this many times and keep the fastest, 1 to 1000 (default 5)")
          ->type_name("N")
          ->check(mccd::cli::integer_in(1, 1000));
      app.add_flag("--verbose", o->verbose, "also list every false positive on stderr");
      app.footer("Exit status: 0 no false negative, 1 any false negative (each is listed on stderr), 2 usage or "
                 "input error. Times are the fastest of --repeat runs, steady_clock around one call.");
      return [o] { return queries(*o); };
    });

}  // namespace
