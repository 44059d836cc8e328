#pragma once
/// @file The command lines of the small bench_* programs (bench_step, bench_queries, bench_graph,
/// bench_ccd), on CLI11 like the `mccd` tool's: bounded numeric options whose messages name the
/// option and the accepted range, and every refusal (a bad option or value, a missing folder, an
/// unreadable file) one line on stderr, "bench_NAME: MESSAGE", with exit status 2.
/// The validators are the `mccd` tool's (tools/options.h).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <string>
#include <system_error>
#include <vector>

#include <CLI/CLI.hpp>

#include <mccd/geometry/error.h>

#include "options.h"

namespace mccd::bench {

using cli::integer_in;  // the validators of the `mccd` tool's options (tools/options.h)
using cli::kExitUsage;  // a refused option or value, or unusable input
using cli::kMaxThreads;
using cli::number_in;
inline constexpr int kMaxRepeats = 1000;  ///< most timed repetitions (--repeat, --rounds, --runs)

/// Accepts a finite decimal number >= 0; otherwise the message quotes the value.
inline CLI::Validator non_negative_number() { return number_in(0, std::numeric_limits<double>::infinity()); }

/// `--threads N` (1 to kMaxThreads) into `threads`, its default shown.
inline CLI::Option* add_threads(CLI::App& app, int& threads) {
  return app.add_option("--threads", threads, "worker threads, 1 to " + std::to_string(kMaxThreads))
      ->type_name("N")
      ->check(integer_in(1, kMaxThreads))
      ->capture_default_str();
}

/// A count of timed repetitions `name` (1 to kMaxRepeats) into `count`; `what` says what is
/// repeated.
inline CLI::Option* add_repeats(CLI::App& app, const std::string& name, int& count, const std::string& what) {
  return app.add_option(name, count, what + ", 1 to " + std::to_string(kMaxRepeats))
      ->type_name("K")
      ->check(integer_in(1, kMaxRepeats))
      ->capture_default_str();
}

/// Accepts what `parse` (one of mccd's parse_method, parse_bvh_build, ...) accepts; otherwise
/// the message is its mccd::Error's, which names the accepted values.
template <class Parse>
CLI::Validator parsed_by(Parse parse) {
  return CLI::Validator(
      [parse](std::string& s) -> std::string {
        try {
          (void)parse(s.c_str());
          return {};
        } catch (const Error& e) {
          return e.what();
        }
      },
      "");
}

/// Parses the command line into `app` (named after the program). Returns -1 when the program
/// goes on; otherwise the exit status to return at once: 0 after --help (printed), kExitUsage
/// after a refusal, printed as one line "NAME: MESSAGE (see 'NAME --help')".
inline int parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string msg = e.what();
    // CLI11 spells some of its messages over several lines; keep them on one.
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    while (!msg.empty() && msg.back() == ' ') msg.pop_back();
    const std::string name = app.get_name();
    std::fprintf(stderr, "%s: %s (see '%s --help')\n", name.c_str(), msg.c_str(), name.c_str());
    return kExitUsage;
  }
  return -1;
}

/// Prints what stopped a program's work as one line "NAME: MESSAGE" ("NAME: PATH: REASON" for a
/// file system error) and returns kExitUsage.
inline int report_failure(const char* name, const std::exception& e) {
  if (const auto* fe = dynamic_cast<const std::filesystem::filesystem_error*>(&e)) {
    const std::string path = fe->path1().empty() ? "" : fe->path1().string() + ": ";
    std::fprintf(stderr, "%s: %s%s\n", name, path.c_str(), fe->code().message().c_str());
  } else {
    std::fprintf(stderr, "%s: %s\n", name, e.what());
  }
  return kExitUsage;
}

/// The frames of a Time-of-Impact step, `dir`/frames/*.ply, sorted by name. Throws mccd::Error
/// naming the folder when it is missing or holds no frame.
inline std::vector<std::string> frame_files(const std::filesystem::path& dir) {
  const std::filesystem::path frames = dir / "frames";
  if (!std::filesystem::is_directory(frames)) throw Error(frames.string() + ": no such folder");
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(frames))
    if (e.path().extension() == ".ply") files.push_back(e.path().string());
  if (files.empty()) throw Error(frames.string() + ": no *.ply frames");
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace mccd::bench
