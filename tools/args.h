#pragma once
/// @file A small command-line parser: `--name value`, `--name=value`, `--flag`, positionals.
#include <set>
#include <string>
#include <vector>

#include <mccd/geometry/error.h>

namespace mccd::cli {

class Args {
 public:
  /// `with_value`: the options that take a value; `flags`: the options that take none.
  /// Anything else starting with "--" is refused.
  Args(const std::vector<std::string>& args, std::set<std::string> with_value, std::set<std::string> flags) {
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string& a = args[i];
      if (a.size() > 2 && a.compare(0, 2, "--") == 0) {
        std::string name = a.substr(2), value;
        const auto eq = name.find('=');
        const bool inline_value = eq != std::string::npos;
        if (inline_value) {
          value = name.substr(eq + 1);
          name = name.substr(0, eq);
        }
        if (with_value.count(name)) {
          if (!inline_value) {
            if (i + 1 >= args.size()) throw Error("option --" + name + " needs a value");
            value = args[++i];
          }
          values_.emplace_back(name, value);
        } else if (flags.count(name) && !inline_value) {
          values_.emplace_back(name, "");
        } else {
          throw Error("unknown option --" + name);
        }
      } else {
        positional_.push_back(a);
      }
    }
  }
  bool has(const std::string& name) const {
    for (auto& [n, v] : values_)
      if (n == name) return true;
    return false;
  }
  /// The last value given for `name`, or `fallback`.
  std::string get(const std::string& name, const std::string& fallback = "") const {
    std::string out = fallback;
    for (auto& [n, v] : values_)
      if (n == name) out = v;
    return out;
  }
  long get_int(const std::string& name, long fallback) const {
    if (!has(name)) return fallback;
    const std::string s = get(name);
    std::size_t used = 0;
    long v = 0;
    try {
      v = std::stol(s, &used);
    } catch (...) {
      used = 0;
    }
    if (used != s.size() || s.empty()) throw Error("option --" + name + ": expected an integer, got '" + s + "'");
    return v;
  }
  double get_double(const std::string& name, double fallback) const {
    if (!has(name)) return fallback;
    const std::string s = get(name);
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(s, &used);
    } catch (...) {
      used = 0;
    }
    if (used != s.size() || s.empty()) throw Error("option --" + name + ": expected a number, got '" + s + "'");
    return v;
  }
  const std::vector<std::string>& positional() const { return positional_; }

 private:
  std::vector<std::pair<std::string, std::string>> values_;
  std::vector<std::string> positional_;
};

}  // namespace mccd::cli
