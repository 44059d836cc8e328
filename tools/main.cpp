// mccd: command-line front end. Sub-commands register themselves (see command.h); this file
// builds the CLI11 application from them, parses, turns every refusal into one line on stderr
// with exit status 2, and runs the chosen command.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <new>

#include <CLI/App.hpp>
#include <CLI/Config.hpp>
#include <CLI/Formatter.hpp>
#include <mccd/geometry/lane_masks.h>

#include "command.h"
#include "interrupt.h"
#include "options.h"

#ifndef MCCD_VERSION
#define MCCD_VERSION "unknown"
#endif

namespace mccd::cli {
std::vector<CommandInfo>& registry() {
  static std::vector<CommandInfo> r;
  return r;
}
}  // namespace mccd::cli

namespace {

using namespace mccd::cli;

const char* kFooter =
    "Exit status: 0 ran and found nothing (no collision; no missed pair), 1 ran and found "
    "collisions (run, like diff or grep; --exit-zero turns this off) or missed pairs "
    "(toi-check, queries), 2 usage or input error. Errors are one line on stderr naming the "
    "file, option or value.\nFirst steps: mccd demo; then mccd run 'frame%03d.ply' "
    "--image first.png. Help on one command: mccd COMMAND --help.";

/// Help lines: names in the first kNameColumn columns, descriptions wrapped to kHelpWidth.
constexpr std::size_t kNameColumn = 30, kHelpWidth = 100;

void wrap_help(CLI::App& app) {
  for (CLI::Option* opt : app.get_options()) opt->description(wrap_text(opt->get_description(), kHelpWidth - kNameColumn));
  app.footer(wrap_text(app.get_footer(), kHelpWidth));
}

/// The first argument that is neither a command nor consumed: a misspelt option or a stray value.
std::string unexpected_message(const std::string& command, const std::string& arg) {
  const std::string prog = command.empty() ? "mccd" : "mccd " + command;
  if (command.empty() && (arg.empty() || arg[0] != '-')) {
    std::string names;
    for (const CommandInfo& c : registry()) names += (names.empty() ? "" : ", ") + c.name;
    return "mccd: error: unknown command '" + arg + "' (commands: " + names + "; see 'mccd --help')";
  }
  const bool option = arg.size() > 1 && arg[0] == '-';
  return prog + ": error: " + (option ? "unknown option " : "unexpected argument ") + arg + " (see '" + prog + " --help')";
}

int run_main(int argc, char** argv) {
  CLI::App app("mccd " MCCD_VERSION ": continuous collision detection for deforming triangle meshes", "mccd");
  app.set_version_flag("--version",
                       std::string("mccd " MCCD_VERSION " (lane kernels: ") +
                           mccd::detail::to_string(mccd::detail::lane_kernels().level) +
                           "; MCCD_SIMD=scalar|sse2|avx2|avx512 asks for a lower level)",
                       "print the version and the vector instructions in use, and exit");
  app.require_subcommand(0, 1);
  app.allow_extras();
  app.get_formatter()->column_width(kNameColumn);

  std::vector<CommandInfo> commands = registry();
  std::stable_sort(commands.begin(), commands.end(),
                   [](const CommandInfo& a, const CommandInfo& b) { return a.order < b.order; });
  std::map<const CLI::App*, std::pair<std::string, Runner>> runners;
  for (const CommandInfo& c : commands) {
    CLI::App* sub = app.add_subcommand(c.name, c.summary);
    sub->allow_extras();
    runners[sub] = {c.name, c.setup(*sub)};
    wrap_help(*sub);
  }
  app.footer(kFooter);
  wrap_help(app);
  if (argc < 2) {
    std::cerr << app.help();
    return kExitUsage;
  }
  const std::string first = argv[1];
  std::string command;
  for (const CommandInfo& c : commands)
    if (c.name == first) command = c.name;
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << one_line_message(e, command) << "\n";
    return kExitUsage;
  }
  if (!app.remaining().empty()) {
    std::cerr << unexpected_message("", app.remaining().front()) << "\n";
    return kExitUsage;
  }
  for (const auto& [sub, named] : runners) {
    if (!sub->parsed()) continue;
    if (!sub->remaining().empty()) {
      std::cerr << unexpected_message(named.first, sub->remaining().front()) << "\n";
      return kExitUsage;
    }
    return named.second();
  }
  std::cerr << app.help();
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  // Before any thread exists, so every thread inherits the blocked SIGINT / SIGTERM.
  start_interrupt_watcher();
  const std::string command = argc > 1 ? argv[1] : "";
  const std::string prog = command.empty() || command[0] == '-' ? "mccd" : "mccd " + command;
  try {
    return run_main(argc, argv);
  } catch (const std::filesystem::filesystem_error& e) {
    // "PATH: what went wrong", like every other error, instead of the library's own wording.
    const std::string path = e.path1().empty() ? "" : e.path1().string() + ": ";
    std::cerr << prog << ": error: " << path << e.code().message() << "\n";
  } catch (const std::bad_alloc&) {
    std::cerr << prog << ": error: out of memory\n";
  } catch (const std::exception& e) {
    std::cerr << prog << ": error: " << e.what() << "\n";
  }
  return kExitUsage;
}
