#pragma once
/// @file Sub-command registry of the `mccd` tool. Each command lives in its own file and
/// registers itself with a static `Command` object.
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace mccd::cli {

/// A command gets its arguments (without the program and command names) and returns the
/// process exit status. It may throw; main prints the message and exits with status 2.
using CommandFn = std::function<int(const std::vector<std::string>& args)>;

struct CommandInfo {
  CommandFn run;
  std::string usage;    ///< one line: "info FILE..."
  std::string summary;  ///< one line of help
};

std::map<std::string, CommandInfo>& registry();

struct Command {
  Command(const std::string& name, std::string usage, std::string summary, CommandFn fn) {
    registry()[name] = CommandInfo{std::move(fn), std::move(usage), std::move(summary)};
  }
};

}  // namespace mccd::cli
