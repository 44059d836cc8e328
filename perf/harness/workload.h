#pragma once
/// @file What the harness times: one mesh and a sequence of positions, stepped in order from
/// a fresh mccd::Scene (step k goes from positions k to k + 1), covering `intervals` frame
/// intervals of the source animation.
#include <string>
#include <vector>

#include <mccd/geometry/mesh.h>

namespace mccd::bench {

struct Workload {
  std::string name;         ///< scene id in the results ("cloth-ball", "cloth-ball-toi-5sub")
  std::string description;  ///< one line for the tables
  TriMesh mesh;             ///< triangles; its positions are positions[0]
  std::vector<Positions> positions;
  int intervals = 0;  ///< frame intervals the steps cover (the unit of "ms per frame")

  std::size_t steps() const { return positions.empty() ? 0 : positions.size() - 1; }
};

/// Where the generated scenes come from and which part of them is timed.
struct GeneratedSource {
  std::string cache_dir;
  std::string size = "full";  ///< tiny, small or full
  std::uint64_t seed = 1;
  int steps = 6;   ///< the last `steps` frame intervals of the sequence (most contact)
};

/// A generated scene (cloth-ball, n-body, bart, skirt), generated into the cache first when
/// absent or stale; the window of its last `steps` intervals.
Workload load_generated(const std::string& name, const GeneratedSource& source);

/// The real cloth-ball step 92 -> 93 of the Time-of-Impact data set under `data_dir`
/// (toi/cloth-ball/frames), as `substeps` linear sub-steps of the one frame interval (1: the
/// whole interval in one step). Throws mccd::Error naming the missing file.
Workload load_toi_cloth_ball(const std::string& data_dir, int substeps);

/// The scene ids load_workload() accepts, in the order of the results.
const std::vector<std::string>& workload_names();
/// By id: the generated scenes by their names, "cloth-ball-toi" (one step) and
/// "cloth-ball-toi-5sub" (five sub-steps). Throws mccd::Error naming the known ids.
Workload load_workload(const std::string& name, const GeneratedSource& source, const std::string& data_dir);

}  // namespace mccd::bench
