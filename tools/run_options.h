#pragma once
/// @file The options `mccd run` and `mccd demo` share, declared once with their bounds and help.
#include <CLI/App.hpp>

#include "run_driver.h"

namespace mccd::cli {

/// --quiet, --verbose.
void add_display_options(CLI::App& app, RunSettings& s);
/// --image, --image-step, --image-size, --camera, --colored. `moment` says which moment the
/// picture shows without --image-step ("the first contact (...)"); `default_image` is the
/// picture written without --image ("" for none).
void add_picture_options(CLI::App& app, RunSettings& s, const std::string& moment, const std::string& default_image);
/// --contacts, --stats, --partial, --exit-zero.
void add_file_options(CLI::App& app, RunSettings& s);
/// --method, --substeps, --min-distance, --volume, --rebuild-sprout, --rebuild-invalid, --threads.
void add_engine_options(CLI::App& app, RunSettings& s);

}  // namespace mccd::cli
