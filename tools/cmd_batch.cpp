// `mccd batch MANIFEST --out DIR`: runs every sequence of a manifest as `mccd run` would, one
// contacts and one statistics file per sequence, and a summary table (CSV and Markdown). Under
// mpirun or srun the sequences are handed out to the ranks as they ask for work, largest
// first; without MPI, or in one process, they run one after another.
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <numeric>
#include <sstream>
#include <thread>

#include <CLI/App.hpp>
#include <nlohmann/json.hpp>

#include <mccd/geometry/atomic_file.h>
#include <mccd/geometry/error.h>

#include "command.h"
#include "mpi/cluster.h"
#include "options.h"
#include "run_driver.h"
#include "run_input.h"
#include "run_options.h"

namespace {

using namespace mccd;
using namespace mccd::cli;
namespace fs = std::filesystem;

/// Message tags: a rank asks for work (with the outcome of its last sequence); rank 0 answers
/// with a sequence's index or -1; rank 0 has written the summary.
constexpr int kAskTag = 3511, kTaskTag = 3512, kDoneTag = 3513;

struct BatchArgs {
  std::string manifest, out, format = "csv";
  bool quiet = false;
  RunSettings defaults;
};

/// One line of the manifest.
struct Sequence {
  int line = 0;
  std::string path, name;
  RunSettings settings;
  double cost = 0;  ///< frames times the first frame's bytes: the order of hand-out
};

/// What became of a sequence (travels from a rank to rank 0 as JSON).
struct Outcome {
  std::string status = "not run", error;
  std::size_t frames = 0, triangles = 0, steps = 0, steps_with_contacts = 0, contacts = 0;
  double first = INFINITY, seconds = 0;
  int rank = 0, exit = 0;
};

nlohmann::json to_json(const Outcome& o) {
  return {{"status", o.status},   {"error", o.error},     {"frames", o.frames},
          {"triangles", o.triangles}, {"steps", o.steps}, {"steps_with_contacts", o.steps_with_contacts},
          {"contacts", o.contacts}, {"first", std::isfinite(o.first) ? nlohmann::json(o.first) : nlohmann::json()},
          {"seconds", o.seconds}, {"rank", o.rank},       {"exit", o.exit}};
}

Outcome from_json(const nlohmann::json& j) {
  Outcome o;
  o.status = j.at("status"), o.error = j.at("error"), o.frames = j.at("frames"), o.triangles = j.at("triangles");
  o.steps = j.at("steps"), o.steps_with_contacts = j.at("steps_with_contacts"), o.contacts = j.at("contacts");
  o.first = j.at("first").is_null() ? INFINITY : double(j.at("first"));
  o.seconds = j.at("seconds"), o.rank = j.at("rank"), o.exit = j.at("exit");
  return o;
}

/// A name usable as a file name: letters, digits, '.', '_', '-'; others become '_'.
std::string file_name(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '_';
  return s;
}

/// The default name of a sequence: a folder's name; for a pattern or a file, the name of the
/// folder it is in (one sequence a folder), else its name without number and extension.
std::string default_name(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::path(path).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();
  if (fs::is_directory(p, ec)) return p.filename().string();
  const std::string folder = p.parent_path().filename().string();
  if (!folder.empty() && folder != "." && folder != "..") return folder;
  std::string stem = p.stem().string();
  const std::size_t pct = stem.find('%');
  if (pct != std::string::npos) stem.erase(pct);
  while (!stem.empty() && (stem.back() == '_' || stem.back() == '-' || stem.back() == '.' ||
                           std::isdigit(static_cast<unsigned char>(stem.back()))))
    stem.pop_back();
  return stem;
}

/// The first word of a line ("double quotes" keep spaces) and the rest.
std::pair<std::string, std::string> first_word(const std::string& line) {
  std::size_t i = line.find_first_not_of(" \t");
  std::string word;
  if (line[i] == '"') {
    const std::size_t e = line.find('"', i + 1);
    if (e == std::string::npos) throw Error("unclosed quote");
    word = line.substr(i + 1, e - i - 1);
    i = e + 1;
  } else {
    const std::size_t e = std::min(line.find_first_of(" \t", i), line.size());
    word = line.substr(i, e - i);
    i = e;
  }
  return {word, i < line.size() ? line.substr(i) : std::string()};
}

/// Reads the manifest: one sequence a line (a frame pattern, a folder, or a frame file list
/// is not: one word), then options of `mccd run`'s engine and --name; '#' starts a comment
/// line. Relative paths are taken from the manifest's folder.
std::vector<Sequence> read_manifest(const BatchArgs& a) {
  std::ifstream in(a.manifest);
  if (!in) throw Error(a.manifest + ": cannot read");
  const fs::path base = fs::absolute(a.manifest).parent_path();
  std::vector<Sequence> out;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    if (!text.empty() && text.back() == '\r') text.pop_back();
    const std::size_t first = text.find_first_not_of(" \t");
    if (first == std::string::npos || text[first] == '#') continue;
    const std::string where = a.manifest + ":" + std::to_string(line) + ": ";
    Sequence s;
    s.line = line;
    s.settings = a.defaults;
    try {
      auto [path, rest] = first_word(text);
      s.path = fs::path(path).is_absolute() ? path : (base / path).string();
      CLI::App app("sequence options", "manifest line");
      add_engine_options(app, s.settings);
      app.add_option("--name", s.name, "the sequence's name in the summary and its files' names");
      app.parse(rest, false);
    } catch (const CLI::ParseError& e) {
      throw Error(where + e.what());
    } catch (const Error& e) {
      throw Error(where + e.what());
    }
    s.name = file_name(s.name.empty() ? default_name(s.path) : s.name);
    if (s.name.empty()) s.name = "line" + std::to_string(line);
    for (const Sequence& o : out)
      if (o.name == s.name)
        throw Error(where + "the name '" + s.name + "' is also line " + std::to_string(o.line) +
                    "'s: give one of them --name");
    s.settings.contacts = (fs::path(a.out) / (s.name + ".contacts." + a.format)).string();
    s.settings.stats = (fs::path(a.out) / (s.name + ".stats.json")).string();
    s.settings.quiet = true;
    s.settings.silent = true;
    out.push_back(std::move(s));
  }
  if (out.empty()) throw Error(a.manifest + ": no sequence in the manifest");
  return out;
}

double estimated_cost(const Sequence& s) {
  try {
    const std::vector<std::string> paths = sequence_paths({s.path});
    std::error_code ec;
    const auto bytes = fs::file_size(paths.at(0), ec);
    return double(paths.size()) * double(ec ? 1 : bytes);
  } catch (const std::exception&) {
    return 0;  // it fails when run, and says why
  }
}

Outcome run_sequence(const BatchArgs& a, const Sequence& s, int rank) {
  Outcome o;
  o.rank = rank;
  RunReport report;
  const auto start = std::chrono::steady_clock::now();
  try {
    const RunInput input = input_from_files({s.path});
    o.exit = run_frames(input, s.settings, "mccd batch: " + s.name, &report, nullptr);
    o.status = "ok";
  } catch (const std::exception& e) {
    o.status = "failed";
    o.error = e.what();
    o.exit = 2;
    std::fprintf(stderr, "mccd batch: %s:%d (%s, rank %d): %s\n", a.manifest.c_str(), s.line, s.name.c_str(), rank,
                 e.what());
  }
  o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  o.frames = report.frames, o.triangles = report.triangles, o.steps = report.totals.steps;
  o.steps_with_contacts = report.totals.steps_with_contacts, o.contacts = report.totals.vf + report.totals.ee;
  o.first = o.contacts ? report.totals.first : INFINITY;
  return o;
}

std::string impact(double t) {
  if (!std::isfinite(t)) return "-";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", t);
  return buf;
}

std::string seconds_text(double s) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.3f", s);
  return buf;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : c == '\n' ? std::string(" ") : std::string(1, c);
  return q + "\"";
}

std::string md_field(std::string s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : c == '\n' ? std::string(" ") : std::string(1, c);
  return out;
}

/// summary.csv and summary.md in the manifest's order, each written atomically.
void write_summary(const BatchArgs& a, const std::vector<Sequence>& seqs, const std::vector<Outcome>& outs) {
  std::string csv = "sequence,line,status,frames,triangles,steps,steps_with_contacts,contacts,first_impact,seconds,rank,"
                    "error\n";
  std::string md = "| sequence | line | status | frames | triangles | steps | steps with contacts | contacts | "
                   "first impact | time (s) | rank | error |\n|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (std::size_t i = 0; i < seqs.size(); ++i) {
    const Sequence& s = seqs[i];
    const Outcome& o = outs[i];
    const std::vector<std::string> f = {s.name,
                                        std::to_string(s.line),
                                        o.status,
                                        std::to_string(o.frames),
                                        std::to_string(o.triangles),
                                        std::to_string(o.steps),
                                        std::to_string(o.steps_with_contacts),
                                        std::to_string(o.contacts),
                                        impact(o.first),
                                        seconds_text(o.seconds),
                                        std::to_string(o.rank),
                                        o.error};
    for (std::size_t k = 0; k < f.size(); ++k) {
      csv += (k ? "," : "") + csv_field(f[k]);
      md += "| " + md_field(f[k]) + " ";
    }
    csv += "\n";
    md += "|\n";
  }
  write_atomically((fs::path(a.out) / "summary.csv").string(), csv);
  write_atomically((fs::path(a.out) / "summary.md").string(), md);
}

int run(BatchArgs& a) {
  Cluster& ranks = cluster();
  const int R = ranks.size(), me = ranks.rank();
  std::error_code ec;
  fs::create_directories(a.out, ec);
  if (!fs::is_directory(a.out, ec)) throw Error("--out " + a.out + ": cannot create the folder");
  const std::vector<Sequence> seqs = read_manifest(a);
  const std::size_t n = seqs.size();

  if (me != 0) {  // a worker: ask, run, report, until told there is no more
    std::string last;
    for (;;) {
      ranks.send(0, kAskTag, last);
      const int i = std::stoi(ranks.recv(0, kTaskTag));
      if (i < 0) break;
      last = to_json(run_sequence(a, seqs[std::size_t(i)], me)).dump();
    }
    (void)ranks.recv(0, kDoneTag);
    return kExitClean;
  }

  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::vector<double> cost(n);
  for (std::size_t i = 0; i < n; ++i) cost[i] = estimated_cost(seqs[i]);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return cost[x] > cost[y]; });
  if (!a.quiet)
    std::printf("mccd batch: %zu sequence%s from %s, %d rank%s x %d thread%s, into %s\n", n, n == 1 ? "" : "s",
                a.manifest.c_str(), R, R == 1 ? "" : "s", a.defaults.threads, a.defaults.threads == 1 ? "" : "s",
                a.out.c_str());
  std::fflush(stdout);

  std::vector<Outcome> outs(n);
  std::mutex mu;
  std::size_t finished = 0;
  auto record = [&](std::size_t i, const Outcome& o) {
    std::lock_guard<std::mutex> lock(mu);
    outs[i] = o;
    ++finished;
    if (a.quiet) return;
    if (o.status == "ok")
      std::printf("[%zu/%zu] %s: %zu frames, %zu triangles, %zu contacts in %zu steps, first impact %s, %.3f s, rank %d\n",
                  finished, n, seqs[i].name.c_str(), o.frames, o.triangles, o.contacts, o.steps_with_contacts,
                  impact(o.first).c_str(), o.seconds, o.rank);
    else
      std::printf("[%zu/%zu] %s: FAILED on rank %d (line %d): %s\n", finished, n, seqs[i].name.c_str(), o.rank,
                  seqs[i].line, o.error.c_str());
    std::fflush(stdout);
  };
  std::atomic<std::size_t> next{0};
  std::vector<int> given(std::size_t(R), -1);  // the sequence each worker runs
  // rank 0's dispatcher: the only thread of rank 0 that calls MPI while its main thread runs
  // sequences of its own
  std::thread dispatcher;
  if (R > 1)
    dispatcher = std::thread([&] {
      try {
        for (int active = R - 1; active > 0;) {
          int src = 0;
          const std::string msg = ranks.recv(Cluster::kAnySource, kAskTag, &src);
          if (!msg.empty()) record(std::size_t(given[std::size_t(src)]), from_json(nlohmann::json::parse(msg)));
          const std::size_t k = next++;
          const int i = k < n ? int(order[k]) : -1;
          given[std::size_t(src)] = i;
          if (i < 0) --active;
          ranks.send(src, kTaskTag, std::to_string(i));
        }
      } catch (const std::exception& e) {
        std::fprintf(stderr, "mccd batch: rank 0's dispatcher: %s; stopping every rank\n", e.what());
        ranks.abort(2);
      }
    });
  for (std::size_t k; (k = next++) < n;) record(order[k], run_sequence(a, seqs[order[k]], 0));
  if (dispatcher.joinable()) dispatcher.join();
  // the others may finish first: nothing they wait for can fail after this
  for (int r = 1; r < R; ++r) ranks.send(r, kDoneTag, std::string());
  write_summary(a, seqs, outs);

  std::size_t failed = 0, found = 0;
  for (const Outcome& o : outs) failed += o.status != "ok", found += o.contacts > 0;
  if (!a.quiet)
    std::printf("mccd batch: %zu of %zu sequences complete, %zu failed, %zu with contacts; summary: %s, %s\n",
                n - failed, n, failed, found, (fs::path(a.out) / "summary.csv").string().c_str(),
                (fs::path(a.out) / "summary.md").string().c_str());
  if (failed) return 2;
  return found && !a.defaults.exit_zero ? kExitFound : kExitClean;
}

const Command reg(
    "batch", "check every sequence of a manifest (one frame pattern or folder a line), over MPI ranks when launched by mpirun",
    25, [](CLI::App& app) -> Runner {
      auto a = std::make_shared<BatchArgs>();
      app.add_option("MANIFEST", a->manifest,
                     "text file, one sequence a line: a frame pattern ('seq1/frame%03d.ply') or a folder, relative "
                     "to the manifest's folder, then optional options of that sequence: --name NAME and the engine "
                     "options below (--substeps 4 --method bvtt ...); '#' starts a comment line")
          ->required()
          ->type_name("FILE");
      app.add_option("--out", a->out,
                     "folder for NAME.contacts.csv (or .json), NAME.stats.json per sequence and summary.csv, "
                     "summary.md (created if missing)")
          ->required()
          ->type_name("DIR");
      app.add_option("--format", a->format, "contacts files as csv (default) or json")
          ->check(CLI::IsMember({"csv", "json"}));
      app.add_flag("--quiet,-q", a->quiet, "print nothing but errors");
      app.add_option_function<std::string>(
             "--partial",
             [a](const std::string& v) { a->defaults.partial = v == "remove" ? Partial::Remove : Partial::Keep; },
             "a sequence that stops early (a frame that cannot be read): keep (default) writes its finished steps "
             "marked incomplete, remove writes no file for it; either way no temporary is left")
          ->type_name("HOW")
          ->check(CLI::IsMember({"keep", "remove"}));
      app.add_flag("--exit-zero", a->defaults.exit_zero, "exit with status 0 even when collisions are found");
      add_engine_options(app, a->defaults);
      app.footer(
          "Each sequence runs as `mccd run SEQUENCE --contacts DIR/NAME.contacts.csv --stats DIR/NAME.stats.json` "
          "would, and gives the same files. Launched by mpirun or srun (a build with MCCD_MPI), rank 0 hands the "
          "sequences out, largest first (frames times the first frame's size), as ranks ask for work, and runs "
          "sequences itself between answers; each rank uses --threads threads. Without MPI they run one by one.\n\n"
          "Exit status: 0 every sequence complete and no collision, 1 collisions found (--exit-zero gives 0), 2 a "
          "sequence failed (named with its manifest line and rank, and marked in the summary) or a usage error.\n"
          "Example: mpirun -n 4 mccd batch sequences.txt --out results --threads 8");
      return [a] { return run(*a); };
    });

}  // namespace
