#pragma once
/// @file The frames of a sequence on disk, as `mccd run` and `mccd batch` take them: files in
/// order, one printf pattern, or one folder (its .ply and .obj files in natural order).
#include <string>
#include <vector>

#include "run_driver.h"

namespace mccd::cli {

/// "frame2" < "frame10": digit runs compared as numbers, the rest as text.
bool natural_less(const std::string& a, const std::string& b);

/// The frame files `given` names (files, one pattern or one folder), in order. Throws
/// mccd::Error when there are none or a folder cannot be listed.
std::vector<std::string> sequence_paths(const std::vector<std::string>& given);

/// Reads the first frame (the triangles) and returns the input of `mccd run` over `given`;
/// later frames are read on demand. Throws mccd::Error for fewer than two frames.
RunInput input_from_files(const std::vector<std::string>& given);

}  // namespace mccd::cli
