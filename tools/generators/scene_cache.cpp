#include "generators/scene_cache.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <mccd/geometry/atomic_file.h>
#include <mccd/geometry/error.h>
#include <mccd/geometry/mesh_io.h>

namespace mccd::gen {

namespace fs = std::filesystem;

namespace {

std::string frame_name(int f) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%03d.ply", f);
  return buf;
}

nlohmann::json expected_manifest(const Generator& g, SceneSize size, std::uint64_t seed) {
  return {{"scene", g.name}, {"generator_version", g.version}, {"seed", seed}, {"size", to_string(size)},
          {"parameters", g.parameters(size)}};
}

// The manifest's fields that decide whether the cache is current, or null when there is none.
nlohmann::json read_manifest(const fs::path& dir) {
  std::ifstream in(dir / "manifest.json");
  if (!in) return nullptr;
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return nullptr;  // unreadable: treated as stale
  }
}

CachedScene describe(const std::string& name, const fs::path& dir, const nlohmann::json& manifest) {
  CachedScene c;
  c.name = name;
  c.dir = dir.string();
  const int frames = manifest.at("frames");
  for (int f = 0; f < frames; ++f) c.frames.push_back((dir / frame_name(f)).string());
  c.vertices = manifest.at("vertices");
  c.triangles = manifest.at("triangles");
  return c;
}

bool is_current(const fs::path& dir, const nlohmann::json& manifest, const nlohmann::json& expected) {
  if (manifest.is_null() || !manifest.contains("frames")) return false;
  for (const auto& [key, value] : expected.items())
    if (!manifest.contains(key) || manifest[key] != value) return false;
  const int frames = manifest["frames"];
  for (int f = 0; f < frames; ++f)
    if (!fs::is_regular_file(dir / frame_name(f))) return false;
  return true;
}

}  // namespace

std::string default_cache_dir() {
  if (const char* c = std::getenv("MCCD_SCENE_CACHE"); c && *c) return c;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return (fs::path(x) / "mccd" / "scenes").string();
  if (const char* h = std::getenv("HOME"); h && *h) return (fs::path(h) / ".cache" / "mccd" / "scenes").string();
  throw Error("scene cache: set MCCD_SCENE_CACHE, XDG_CACHE_HOME or HOME, or name a folder");
}

std::string scene_dir(const std::string& cache_dir, const std::string& name, SceneSize size, std::uint64_t seed) {
  return (fs::path(cache_dir) / (name + "-" + to_string(size) + "-seed" + std::to_string(seed))).string();
}

CachedScene ensure_scene(const std::string& name, SceneSize size, std::uint64_t seed, const std::string& cache_dir,
                         bool force) {
  const Generator& g = find_generator(name);
  const fs::path dir = scene_dir(cache_dir, name, size, seed);
  nlohmann::json manifest = expected_manifest(g, size, seed);
  if (!force) {
    const nlohmann::json found = read_manifest(dir);
    if (is_current(dir, found, manifest)) return describe(name, dir, found);
  }
  std::error_code ec;
  fs::create_directories(dir.parent_path(), ec);
  if (ec) throw Error(dir.parent_path().string() + ": cannot create the scene cache: " + ec.message());
  fs::path tmp = dir;
  tmp += ".tmp" + std::to_string(::getpid());
  fs::remove_all(tmp, ec);
  fs::create_directory(tmp, ec);
  if (ec) throw Error(tmp.string() + ": cannot create: " + ec.message());
  const auto start = std::chrono::steady_clock::now();
  try {
    int frames = 0;
    g.run(manifest["parameters"], seed, [&](int f, const TriMesh& mesh) {
      if (f == 0) {
        manifest["vertices"] = mesh.num_vertices();
        manifest["triangles"] = mesh.num_faces();
      }
      validate_mesh(mesh);
      write_ply((tmp / frame_name(f)).string(), mesh);
      frames = f + 1;
    });
    manifest["frames"] = frames;
    write_atomically((tmp / "manifest.json").string(), manifest.dump(2) + "\n");
    fs::remove_all(dir);
    fs::rename(tmp, dir);
  } catch (const std::exception& e) {
    fs::remove_all(tmp, ec);
    if (dynamic_cast<const Error*>(&e)) throw;
    throw Error(dir.string() + ": generating " + name + ": " + e.what());
  }
  CachedScene c = describe(name, dir, manifest);
  c.generated = true;
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return c;
}

}  // namespace mccd::gen
