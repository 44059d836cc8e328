#include "run_input.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>

#include <oneapi/tbb/task_arena.h>

#include <mccd/geometry/error.h>
#include <mccd/geometry/frame_sequence.h>
#include <mccd/geometry/mesh_io.h>

#include "fixtures/scenes.h"

namespace mccd::cli {

bool natural_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) && std::isdigit(static_cast<unsigned char>(b[j]))) {
      std::size_t i2 = i, j2 = j;
      while (i2 < a.size() && std::isdigit(static_cast<unsigned char>(a[i2]))) ++i2;
      while (j2 < b.size() && std::isdigit(static_cast<unsigned char>(b[j2]))) ++j2;
      std::string x = a.substr(i, i2 - i), y = b.substr(j, j2 - j);
      x.erase(0, std::min(x.find_first_not_of('0'), x.size()));
      y.erase(0, std::min(y.find_first_not_of('0'), y.size()));
      if (x.size() != y.size()) return x.size() < y.size();
      if (x != y) return x < y;
      i = i2, j = j2;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

namespace {

/// The mesh files (.ply, .obj) of a folder, in natural order of their names.
std::vector<std::string> folder_frames(const std::filesystem::path& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::string ext = it->path().extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (it->is_regular_file() && (ext == ".ply" || ext == ".obj")) out.push_back(it->path().string());
  }
  if (ec) throw Error(dir.string() + ": cannot list: " + ec.message());
  std::sort(out.begin(), out.end(), natural_less);
  if (out.empty()) throw Error(dir.string() + ": no .ply or .obj frames in this folder");
  return out;
}

}  // namespace

std::vector<std::string> sequence_paths(const std::vector<std::string>& given) {
  std::error_code ec;
  const bool folder = given.size() == 1 && std::filesystem::is_directory(given[0], ec);
  return folder ? folder_frames(given[0]) : frame_paths(given);
}

RunInput input_from_files(const std::vector<std::string>& given) {
  std::error_code ec;
  const bool folder = given.size() == 1 && std::filesystem::is_directory(given[0], ec);
  const std::vector<std::string> paths = sequence_paths(given);
  // a path that is not there is named as such before anything is counted or read
  for (const std::string& p : paths)
    if (!std::filesystem::exists(p, ec)) throw Error(p + ": cannot open: " + std::strerror(ENOENT));
  if (paths.size() < 2)
    throw Error("need at least two frames, got " + std::to_string(paths.size()) + " (" + paths.front() + ")");
  RunInput in;
  in.description = given.size() == 1 && !folder ? given[0]
                                      : std::filesystem::path(paths.front()).filename().string() + " .. " +
                                            std::filesystem::path(paths.back()).filename().string();
  in.frame_files = paths;
  in.meshes.push_back(read_mesh(paths[0]));
  in.frames = paths.size();
  const TriMesh& first = in.meshes[0];
  in.frame = [paths, &first](std::size_t i) {
    if (i == 0) return std::vector<Positions>{first.vertices};
    return std::vector<Positions>{read_frame(paths[i], i, first, paths[0])};
  };
  return in;
}

void check_scene_size(int size_k, int frames) {
  if (static_cast<long>(size_k) * frames > kMaxSizeTimesFrames)
    throw Error("--size " + std::to_string(size_k) + " with --frames " + std::to_string(frames) +
                ": a built-in scene is held in memory, so --size times --frames may be at most " +
                std::to_string(kMaxSizeTimesFrames));
}

RunInput input_from_scene(const std::string& name, int size_k, int frames, int threads) {
  check_scene_size(size_k, frames);
  return input_from_generated([&] { return make_scene(name, size_k, frames); }, threads, "built-in scene " + name);
}

RunInput input_from_generated(const std::function<AnimatedScene()>& make, int threads, std::string description) {
  std::shared_ptr<AnimatedScene> scene;
  tbb::task_arena arena(threads > 0 ? threads : int(tbb::task_arena::automatic));
  arena.execute([&] { scene = std::make_shared<AnimatedScene>(make()); });
  RunInput in;
  in.description = std::move(description);
  in.meshes = scene->meshes;
  in.frames = scene->frames.size();
  in.frame = [scene](std::size_t i) { return scene->frames.at(i); };
  return in;
}

}  // namespace mccd::cli
