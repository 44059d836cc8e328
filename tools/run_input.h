#pragma once
/// @file What `mccd run` steps through: frame files (given one by one, as a printf pattern, or
/// as a folder) or a built-in scene, as a RunInput for run_frames(). Shared by the command
/// line and the Python module (tools/python), so both read the same frames in the same order.
#include <string>
#include <vector>

#include "run_driver.h"

namespace mccd::cli {

/// Built-in scenes are held in memory: their size in thousands of triangles times their
/// frame count is bounded so that they fit (about 12 kB per thousand triangles and frame).
constexpr long kMaxSizeTimesFrames = 20000;

/// "frame2" < "frame10": digit runs compared as numbers, the rest as text.
bool natural_less(const std::string& a, const std::string& b);
/// The mesh files (.ply, .obj) of a folder, in natural order of their names; throws
/// mccd::Error when there are none.
std::vector<std::string> folder_frames(const std::string& dir);
/// The frames of files given in order, one printf pattern ("frame%03d.ply"), or one folder.
/// Reads the first frame now (its triangles are the sequence's), the others when asked.
/// Throws mccd::Error when fewer than two frames are found.
RunInput input_from_files(const std::vector<std::string>& given);
/// Refuses a built-in scene of `size_k` thousand triangles and `frames` frames whose
/// product exceeds kMaxSizeTimesFrames (mccd::Error naming both).
void check_scene_size(int size_k, int frames);
/// A built-in scene by name (cloth, spheres, random, tube, drape), `size_k` thousand
/// triangles, `frames` frames; throws mccd::Error when size_k * frames exceeds
/// kMaxSizeTimesFrames or the name is unknown.
RunInput input_from_scene(const std::string& name, int size_k, int frames);

}  // namespace mccd::cli
