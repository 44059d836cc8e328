#pragma once
/// @file The option layer of the `mccd` tool, on CLI11: strict, bounded numeric options whose
/// messages name the option and the accepted range, the options several commands share
/// (method, threads, minimum distance), and the exit statuses. No option accepts a value that
/// would exhaust memory or run until killed; the bounds are stated in each option's help.
#include <string>
#include <vector>

#include <CLI/App.hpp>

#include <mccd/core/options.h>
#include <mccd/geometry/positions.h>

namespace mccd::cli {

/// Exit statuses of every command (`mccd --help` documents them).
inline constexpr int kExitClean = 0;  ///< ran; nothing to report (no collision, no miss)
inline constexpr int kExitFound = 1;  ///< ran; collisions found (run), pairs missed (toi-check, queries)
inline constexpr int kExitUsage = 2;  ///< usage or input error (bad option, unreadable or invalid file)

/// Most worker threads --threads accepts.
inline constexpr int kMaxThreads = 1024;

/// Accepts a whole decimal integer in [lo, hi]; otherwise the message is
/// "expected an integer from LO to HI, got 'VALUE'".
CLI::Validator integer_in(long long lo, long long hi);
/// Accepts a finite decimal number in [lo, hi] (in (lo, hi] when `lo_open`); otherwise the
/// message names the range and quotes the value. `hi` may be +infinity (no upper bound).
CLI::Validator number_in(double lo, double hi, bool lo_open = false);

/// `--method NAME` (bruteforce, traverse, phc, fbd, or its alias front) into `method`.
CLI::Option* add_method_option(CLI::App& app, Method& method);
/// `--bvh median|sah`, `--leaf-size K` (1 to 21) and `--representatives default|leaf|canonical`
/// into `bvh`, `leaf_size` and `rule`.
/// --bvh, --leaf-size, --representatives and --no-self-culling.
void add_bvh_options(CLI::App& app, BvhBuild& bvh, unsigned& leaf_size, Representatives& rule, bool& self_culling);
/// `--threads N` (1 to kMaxThreads) into `threads`, which keeps its default (the machine's
/// hardware concurrency) when absent.
CLI::Option* add_threads_option(CLI::App& app, int& threads);
/// `--min-distance D` (finite, >= 0) into `d`; `extra` is appended to the help.
CLI::Option* add_min_distance_option(CLI::App& app, double& d, const std::string& extra = "");

/// The largest --min-distance a scene accepts: this fraction of the diagonal of its first
/// frame's bounding box. Beyond it nearly every pair of a scene is a contact, and the run
/// would fill memory with them.
inline constexpr double kMaxMinDistanceFraction = 0.01;
/// Throws mccd::Error when `d` exceeds kMaxMinDistanceFraction of the bounding-box diagonal
/// of `frame` (all meshes together), naming both numbers.
void check_min_distance(double d, const std::vector<Positions>& frame);

/// `text` with its lines broken at spaces to at most `width` characters (longer words stay
/// whole); existing line breaks are kept.
std::string wrap_text(const std::string& text, std::size_t width);

/// The one-line message for a CLI11 parse error of `command` ("" for the top level).
std::string one_line_message(const CLI::Error& e, const std::string& command);

}  // namespace mccd::cli
