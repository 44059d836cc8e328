#pragma once
/// @file The frames of a sequence on disk, as `mccd run` and `mccd batch` take them: files in
/// order, one printf pattern, or one folder (its .ply and .obj files in natural order); and
/// the built-in scenes of `mccd run --scene`. Shared with the Python module (tools/python).
#include <functional>
#include <string>
#include <vector>

#include "fixtures/scenes.h"
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

/// Built-in scenes are held in memory: their size in thousands of triangles times their
/// frame count is bounded so that they fit (about 12 kB per thousand triangles and frame).
constexpr long kMaxSizeTimesFrames = 20000;
/// Refuses a built-in scene of `size_k` thousand triangles and `frames` frames whose product
/// exceeds kMaxSizeTimesFrames (mccd::Error naming both).
void check_scene_size(int size_k, int frames);
/// The input of `mccd run --scene NAME`: a built-in scene (cloth, spheres, random, tube,
/// drape; fixtures/scenes.h) of about `size_k` thousand triangles and `frames` frames, held in
/// memory, generated on `threads` threads (0: all; the drape's simulation runs in parallel).
/// Throws mccd::Error for an unknown name or a scene too large (check_scene_size).
RunInput input_from_scene(const std::string& name, int size_k, int frames, int threads = 0);
/// The input of a scene that `make()` generates, held in memory, generated on `threads`
/// threads (0: all), described as `description` (input_from_scene, `mccd demo`).
RunInput input_from_generated(const std::function<AnimatedScene()>& make, int threads, std::string description);

}  // namespace mccd::cli
