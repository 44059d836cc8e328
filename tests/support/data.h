#pragma once
/// @file Where the shared ground-truth data lives, for tests that read it.
#include <cstdlib>
#include <filesystem>
#include <string>

namespace mccd::test {

/// `$MCCD_DATA_DIR`, else the `../shared/data` beside the checkout.
inline std::filesystem::path data_dir() {
  if (const char* env = std::getenv("MCCD_DATA_DIR")) return env;
  return MCCD_DEFAULT_DATA_DIR;
}

/// Path of the built `mccd` tool.
inline std::string cli_path() { return MCCD_CLI_PATH; }

}  // namespace mccd::test

/// Skips the current test, saying why, when a data file or folder is absent.
#define MCCD_REQUIRE_DATA(path)                                                                   \
  do {                                                                                            \
    if (!std::filesystem::exists(path))                                                           \
      GTEST_SKIP() << "shared data not found at " << (path) << " (set MCCD_DATA_DIR to run this)"; \
  } while (0)
