#pragma once
/// @file The real cloth-ball step of the shared data (its two frames, 92 and 93) as a two-frame
/// scene, for the tests that run it beside the generated scenes.
#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <mccd/geometry/frame_sequence.h>

#include "fixtures/scenes.h"
#include "support/data.h"

namespace mccd::test {

/// The folder of the step's frames (check it with MCCD_REQUIRE_DATA before reading).
inline std::filesystem::path cloth_ball_frames() { return data_dir() / "toi" / "cloth-ball" / "frames"; }

/// The step read from `dir`, its `.ply` files in name order (exactly two of them).
inline AnimatedScene cloth_ball_step(const std::filesystem::path& dir) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".ply") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  if (files.size() != 2) throw std::runtime_error("expected two .ply frames in " + dir.string());
  const FrameSequence seq = read_frames(files);
  AnimatedScene s;
  s.name = "cloth-ball";
  s.meshes = {seq.mesh};
  s.frames = {{seq.frames[0]}, {seq.frames[1]}};
  return s;
}

}  // namespace mccd::test
