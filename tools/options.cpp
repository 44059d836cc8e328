#include "options.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <system_error>

#include <oneapi/tbb/info.h>

#include <mccd/geometry/error.h>
#include <mccd/geometry/mesh.h>

namespace mccd::cli {

namespace {

/// At most this many characters of a refused value are quoted back.
constexpr std::size_t kQuoteMax = 40;

std::string quote_value(const std::string& s) {
  return "'" + (s.size() <= kQuoteMax ? s : s.substr(0, kQuoteMax) + "...") + "'";
}

std::string format_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

CLI::Validator integer_in(long long lo, long long hi) {
  const std::string range = std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, range](std::string& s) -> std::string {
        long long v = 0;
        const char* end = s.data() + s.size();
        const auto [ptr, ec] = std::from_chars(s.data(), end, v);
        if (s.empty() || ptr != end || (ec != std::errc() && ec != std::errc::result_out_of_range))
          return "expected an integer from " + range + ", got " + quote_value(s);
        if (ec == std::errc::result_out_of_range || v < lo || v > hi)
          return "must be from " + range + ", got " + quote_value(s);
        return {};
      },
      "");
}

CLI::Validator number_in(double lo, double hi, bool lo_open) {
  const std::string range = std::isinf(hi) ? (lo_open ? "greater than " : "at least ") + format_number(lo)
                                           : (lo_open ? "greater than " : "from ") + format_number(lo) + " to " +
                                                 format_number(hi);
  return CLI::Validator(
      [lo, hi, lo_open, range](std::string& s) -> std::string {
        double v = 0;
        const char* end = s.data() + s.size();
        const auto [ptr, ec] = std::from_chars(s.data(), end, v);
        if (s.empty() || ptr != end || ec != std::errc() || !std::isfinite(v))
          return "expected a finite number " + range + ", got " + quote_value(s);
        if (v > hi || v < lo || (lo_open && v == lo)) return "must be " + range + ", got " + quote_value(s);
        return {};
      },
      "");
}

void add_bvh_options(CLI::App& app, BvhBuild& bvh, unsigned& leaf_size, Representatives& rule, bool& self_culling) {
  app.add_option_function<std::string>(
         "--bvh", [&bvh](const std::string& v) { bvh = parse_bvh_build(v.c_str()); },
         "how the scene BVH is built: sah (binned surface area heuristic, default) or median (the paper's "
         "spatial median, one triangle per leaf: reproduces its experiments)")
      ->type_name("NAME")
      ->check(CLI::IsMember({"median", "sah"}));
  app.add_option("--leaf-size", leaf_size,
                 "triangles per BVH leaf, 1 to 21 (default: 21 with sah, 1 with median)")
      ->type_name("K")
      ->check(integer_in(1, 21));
  app.add_option_function<std::string>(
         "--representatives", [&rule](const std::string& v) { rule = parse_representatives(v.c_str()); },
         "where each vertex-face and edge-edge pair is tested (the same contacts either way): leaf (every "
         "vertex and edge belongs to the BVH leaf of its first triangle; the default with sah) or canonical "
         "(the paper's first non-adjacent triangle pair, with its orphan set; the default with median)")
      ->type_name("NAME")
      ->check(CLI::IsMember({"default", "leaf", "canonical"}));
  app.add_flag_function(
      "--no-self-culling", [&self_culling](std::int64_t) { self_culling = false; },
      "test every patch's own pairs, skipping none certified free of self-collision (the same contacts; "
      "with the canonical representatives, or a minimum distance, nothing is culled anyway)");
}

CLI::Option* add_method_option(CLI::App& app, Method& method) {
  auto* opt = app.add_option_function<std::string>(
      "--method", [&method](const std::string& s) { method = parse_method(s.c_str()); },
      "how candidate pairs are found: bruteforce (every feature pair, the oracle), traverse (BVTT "
      "from the root every step, serial), phc (from the root, parallel subtasks), fbd (the front "
      "tracked from step to step, parallel; alias front). All four report identical contacts. "
      "Default: fbd");
  opt->type_name("NAME");
  opt->check(CLI::Validator(
      [](std::string& s) -> std::string {
        try {
          (void)parse_method(s.c_str());
          return {};
        } catch (const Error& e) {
          return e.what();
        }
      },
      ""));
  return opt;
}

CLI::Option* add_threads_option(CLI::App& app, int& threads) {
  threads = tbb::info::default_concurrency();
  return app
      .add_option("--threads", threads,
                  "worker threads, 1 to " + std::to_string(kMaxThreads) + " (default: this machine's " +
                      std::to_string(threads) + ")")
      ->type_name("N")
      ->check(integer_in(1, kMaxThreads));
}

CLI::Option* add_min_distance_option(CLI::App& app, double& d, const std::string& extra) {
  return app
      .add_option("--min-distance", d,
                  "report pairs that come within this distance as contacts (a finite number >= 0; "
                  "default 0)" + extra)
      ->type_name("D")
      ->check(number_in(0, std::numeric_limits<double>::infinity()));
}

void check_min_distance(double d, const std::vector<Positions>& frame) {
  Bounds3 all{Vec3::Constant(HUGE_VAL), Vec3::Constant(-HUGE_VAL)};
  for (const Positions& p : frame) {
    const Bounds3 b = bounding_box(p);
    all.min = all.min.cwiseMin(b.min);
    all.max = all.max.cwiseMax(b.max);
  }
  const double diagonal = frame.empty() || !(all.max.x() >= all.min.x()) ? 0.0 : (all.max - all.min).norm();
  const double limit = kMaxMinDistanceFraction * diagonal;
  if (d > limit)
    throw Error("--min-distance " + format_number(d) + " is larger than " +
                format_number(100 * kMaxMinDistanceFraction) + "% of the scene's size (bounding box diagonal " +
                format_number(diagonal) + " at the first frame): at most " + format_number(limit) +
                " is accepted, beyond which nearly every pair is a contact");
}

std::string wrap_text(const std::string& text, std::size_t width) {
  std::string out, line;
  std::size_t at = 0;
  auto flush_line = [&] {
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out += line;
    line.clear();
  };
  while (at < text.size()) {
    if (text[at] == '\n') {
      flush_line();
      out += '\n';
      ++at;
      continue;
    }
    const std::size_t end = std::min(text.find_first_of(" \n", at), text.size());
    const std::string word = text.substr(at, end - at);
    if (!line.empty() && line.size() + word.size() > width) {
      flush_line();
      out += '\n';
    }
    line += word;
    at = end;
    if (at < text.size() && text[at] == ' ') {
      if (!line.empty()) line += ' ';
      ++at;
    }
  }
  flush_line();
  return out;
}

std::string one_line_message(const CLI::Error& e, const std::string& command) {
  std::string msg = e.what();
  // CLI11 spells some of its messages over several lines; keep them on one.
  for (char& c : msg)
    if (c == '\n') c = ' ';
  while (!msg.empty() && msg.back() == ' ') msg.pop_back();
  const std::string prog = command.empty() ? "mccd" : "mccd " + command;
  return prog + ": error: " + msg + " (see '" + prog + " --help')";
}

}  // namespace mccd::cli
