#include "harness/workload.h"

#include <algorithm>
#include <filesystem>

#include <mccd/geometry/error.h>
#include <mccd/geometry/frame_sequence.h>
#include <mccd/geometry/mesh_io.h>

#include "generators/scene_cache.h"

namespace mccd::bench {

Workload load_generated(const std::string& name, const GeneratedSource& source) {
  if (source.steps < 1) throw Error("--steps: must be at least 1");
  const gen::CachedScene cached = gen::ensure_scene(name, gen::parse_size(source.size), source.seed, source.cache_dir);
  const std::size_t frames = cached.frames.size();
  const std::size_t first = frames - std::min<std::size_t>(frames, std::size_t(source.steps) + 1);
  Workload w;
  w.name = name;
  w.mesh = read_mesh(cached.frames[first]);
  w.positions.push_back(w.mesh.vertices);
  for (std::size_t f = first + 1; f < frames; ++f)
    w.positions.push_back(read_frame(cached.frames[f], f, w.mesh, cached.frames[first]));
  w.intervals = int(w.steps());
  w.description = gen::find_generator(name).description + std::string(", frames ") + std::to_string(first) + "-" +
                  std::to_string(frames - 1) + " of " + std::to_string(frames) + " (" + source.size + ", seed " +
                  std::to_string(source.seed) + ")";
  return w;
}

Workload load_toi_cloth_ball(const std::string& data_dir, int substeps) {
  if (substeps < 1) throw Error("cloth-ball-toi: sub-steps must be at least 1");
  const std::filesystem::path dir = std::filesystem::path(data_dir) / "toi" / "cloth-ball" / "frames";
  const std::string start = (dir / "cloth_ball92.ply").string(), end = (dir / "cloth_ball93.ply").string();
  for (const std::string& f : {start, end})
    if (!std::filesystem::is_regular_file(f)) throw Error(f + ": not found (the Time-of-Impact data; see --data)");
  Workload w;
  w.name = substeps == 1 ? "cloth-ball-toi" : "cloth-ball-toi-" + std::to_string(substeps) + "sub";
  w.description = "the real cloth-ball step 92->93 (Time-of-Impact data set), " +
                  (substeps == 1 ? std::string("one step") : std::to_string(substeps) + " linear sub-steps");
  w.mesh = read_mesh(start);
  const Positions p1 = read_frame(end, 1, w.mesh, start);
  const Positions& p0 = w.mesh.vertices;
  w.positions.push_back(p0);
  for (int k = 1; k <= substeps; ++k) {
    const double t = double(k) / substeps;
    Positions p(p0.rows());
    for (std::size_t i = 0; i < p.xyz().size(); ++i) p.xyz()[i] = k == substeps ? p1.xyz()[i] : (1 - t) * p0.xyz()[i] + t * p1.xyz()[i];
    w.positions.push_back(std::move(p));
  }
  w.intervals = 1;
  return w;
}

const std::vector<std::string>& workload_names() {
  static const std::vector<std::string> names{"cloth-ball", "n-body", "bart", "skirt", "cloth-ball-toi", "cloth-ball-toi-5sub"};
  return names;
}

Workload load_workload(const std::string& name, const GeneratedSource& source, const std::string& data_dir) {
  if (name == "cloth-ball-toi") return load_toi_cloth_ball(data_dir, 1);
  if (name == "cloth-ball-toi-5sub") return load_toi_cloth_ball(data_dir, 5);
  for (const gen::Generator& g : gen::generators())
    if (name == g.name) return load_generated(name, source);
  std::string known;
  for (const std::string& n : workload_names()) known += (known.empty() ? "" : ", ") + n;
  throw Error("unknown scene '" + name + "': expected one of " + known);
}

}  // namespace mccd::bench
