#pragma once
/// @file Generated frame sequences on disk for the `mccd batch` and MPI tests: folding cloths
/// of several sizes and lengths written as PLY frames, one folder each, and the helpers to
/// compare what `mccd run` and `mccd batch` write.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fixtures/scenes.h"
#include "support/cli.h"

namespace mccd::test {

struct SequenceOnDisk {
  std::string name;     ///< folder name, the batch's default sequence name
  std::string pattern;  ///< absolute printf pattern of its frames
  std::size_t frames = 0;
};

/// `count` folding cloths (n = 8 + 2 i grid cells, 6 + i frames) as folders `dir/clothI`.
inline std::vector<SequenceOnDisk> write_sequences(const std::filesystem::path& dir, int count) {
  std::vector<SequenceOnDisk> out;
  for (int i = 0; i < count; ++i) {
    const AnimatedScene s = make_folding_cloth(8 + 2 * i, 6 + i);
    std::vector<Positions> frames;
    for (const auto& f : s.frames) frames.push_back(f[0]);
    const std::filesystem::path sub = dir / ("cloth" + std::to_string(i));
    std::filesystem::create_directories(sub);
    out.push_back({"cloth" + std::to_string(i), write_frames(sub, "frame", s.meshes[0], frames), frames.size()});
  }
  return out;
}

/// The file of frame `i` of a pattern like ".../frame%03d.ply".
inline std::string frame_file(const std::string& pattern, std::size_t i) {
  char buf[4096];
  std::snprintf(buf, sizeof buf, pattern.c_str(), int(i));
  return buf;
}

/// A statistics or contacts JSON file without its timing fields (and without "input", which
/// names how the run was given).
inline nlohmann::json without_times(nlohmann::json j) {
  j.erase("wall_seconds");
  j.erase("step_seconds");
  j.erase("input");
  if (j.contains("summary")) {
    j["summary"].erase("wall_seconds");
    j["summary"].erase("step_seconds");
  }
  if (j.contains("steps") && j["steps"].is_array())
    for (auto& s : j["steps"]) s.erase("seconds");
  return j;
}

}  // namespace mccd::test
