// mccd_scenes: generates the benchmark scenes into the scene cache (or finds them there) and
// prints where their frames are.
//   mccd_scenes [SCENE...] [--size tiny|small|full] [--seed N] [--cache DIR] [--force] [--list]
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include <mccd/geometry/error.h>

#include "generators/scene_cache.h"

using namespace mccd;

int main(int argc, char** argv) {
  CLI::App app{"Generates the benchmark scenes (cloth-ball, n-body, bart, skirt) as PLY frames in a cache folder,\n"
               "once per generator version, seed and size; later runs find them there."};
  std::vector<std::string> names;
  std::string size_name = "full", cache;
  std::uint64_t seed = 1;
  bool force = false, list = false;
  app.add_option("scenes", names, "scenes to generate (default: all)");
  app.add_option("--size", size_name, "tiny, small or full")->capture_default_str();
  app.add_option("--seed", seed, "random seed")->capture_default_str();
  app.add_option("--cache", cache, "cache folder (default: $MCCD_SCENE_CACHE, $XDG_CACHE_HOME/mccd/scenes or ~/.cache/mccd/scenes)");
  app.add_flag("--force", force, "generate again even when the cache is current");
  app.add_flag("--list", list, "list the scenes and exit");
  CLI11_PARSE(app, argc, argv);
  try {
    if (list) {
      for (const gen::Generator& g : gen::generators()) std::printf("%-11s %s\n", g.name, g.description);
      return 0;
    }
    const gen::SceneSize size = gen::parse_size(size_name);
    if (cache.empty()) cache = gen::default_cache_dir();
    if (names.empty())
      for (const gen::Generator& g : gen::generators()) names.push_back(g.name);
    for (const std::string& name : names) {
      const gen::CachedScene s = gen::ensure_scene(name, size, seed, cache, force);
      std::printf("%-11s %7zu triangles %4zu frames  %s  %s\n", s.name.c_str(), s.triangles, s.frames.size(), s.dir.c_str(),
                  s.generated ? ("generated in " + std::to_string(s.seconds) + " s").c_str() : "cached");
      std::fflush(stdout);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mccd_scenes: %s\n", e.what());
    return 2;
  }
  return 0;
}
