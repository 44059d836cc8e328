// mccd: command-line front end. Sub-commands register themselves (see command.h).
#include <cstdio>
#include <exception>
#include <iostream>

#include "command.h"

namespace mccd::cli {
std::map<std::string, CommandInfo>& registry() {
  static std::map<std::string, CommandInfo> r;
  return r;
}
}  // namespace mccd::cli

static void usage(std::ostream& os) {
  os << "mccd: continuous collision detection for deforming triangle meshes\n\nusage:\n";
  for (auto& [name, c] : mccd::cli::registry()) os << "  mccd " << c.usage << "\n      " << c.summary << "\n";
}

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h" ||
      std::string(argv[1]) == "help") {
    usage(argc < 2 ? std::cerr : std::cout);
    return argc < 2 ? 2 : 0;
  }
  auto& reg = mccd::cli::registry();
  auto it = reg.find(argv[1]);
  if (it == reg.end()) {
    std::cerr << "mccd: unknown command '" << argv[1] << "'\n";
    usage(std::cerr);
    return 2;
  }
  std::vector<std::string> args(argv + 2, argv + argc);
  try {
    return it->second.run(args);
  } catch (const std::exception& e) {
    std::cerr << "mccd " << argv[1] << ": error: " << e.what() << "\n";
    return 2;
  }
}
