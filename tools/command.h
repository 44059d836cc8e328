#pragma once
/// @file Sub-command registry of the `mccd` tool. Each command lives in its own file and
/// registers itself with a static `Command` object; main builds the CLI11 application from
/// the registry, parses, and runs the chosen command.
#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace mccd::cli {

/// Runs a command with the values parsed into it; returns the process exit status. It may
/// throw: main prints the message on one line and exits with status 2.
using Runner = std::function<int()>;
/// Declares a command's options and positionals on `app` (the command's own CLI11 sub-app,
/// whose description is already set) and returns the function that runs it.
using Setup = std::function<Runner(CLI::App& app)>;

struct CommandInfo {
  std::string name;     ///< "run"
  std::string summary;  ///< one line for `mccd --help`
  int order;            ///< position in `mccd --help` (smaller first)
  Setup setup;
};

/// Every registered command, in registration order (main sorts them by `order`).
std::vector<CommandInfo>& registry();

struct Command {
  Command(std::string name, std::string summary, int order, Setup setup) {
    registry().push_back(CommandInfo{std::move(name), std::move(summary), order, std::move(setup)});
  }
};

}  // namespace mccd::cli
