#include "run_options.h"

#include <charconv>
#include <limits>

#include "options.h"

namespace mccd::cli {

namespace {

/// Most pixels a picture may have (4096 x 2048); it is drawn 2 x 2 supersampled.
constexpr long long kMaxPixels = 4096LL * 2048;

/// "WxH" into width and height, each 16 to 4096, at most kMaxPixels in all.
CLI::Validator image_size() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        const std::size_t x = s.find('x');
        int w = 0, h = 0;
        const bool ok = x != std::string::npos &&
                        std::from_chars(s.data(), s.data() + x, w).ptr == s.data() + x &&
                        std::from_chars(s.data() + x + 1, s.data() + s.size(), h).ptr == s.data() + s.size() &&
                        x > 0 && x + 1 < s.size();
        if (!ok || w < 16 || h < 16 || w > 4096 || h > 4096 || (long long)w * h > kMaxPixels)
          return "expected WIDTHxHEIGHT, each from 16 to 4096 and at most 8.4 million pixels (e.g. 1200x900), got '" +
                 s.substr(0, 40) + "'";
        return {};
      },
      "");
}

}  // namespace

void add_display_options(CLI::App& app, RunSettings& s) {
  app.add_flag("--quiet,-q", s.quiet, "no per-step table and no progress bar: the header and the summary only");
  app.add_flag("--verbose,-v", s.verbose,
               "add the statistics columns to the table (bounding-volume and elementary tests, front size, sprouted "
               "and invalidated nodes, rebuilds, orphan pairs tested), with a legend");
}

void add_picture_options(CLI::App& app, RunSettings& s, const std::string& moment, const std::string& default_image) {
  app.add_option("--image", s.image,
                 "draw the meshes at " + moment +
                     " as a PNG (.png) or JPEG (.jpg, .jpeg; other extensions are refused), the triangles in "
                     "contact in red (red showing through where they are hidden), from a camera framing them, with "
                     "a caption (what was run, the step and its frame time, the contacts shown) and a legend of "
                     "every colour used across the top (none in a picture under 245 pixels wide, or where they would "
                     "take over two fifths of its height); written after the last step" +
                     (default_image.empty() ? std::string() : " (default " + default_image + ")"))
      ->type_name("FILE.png|FILE.jpg");
  app.add_option_function<std::size_t>(
         "--image-step", [&s](std::size_t k) { s.image_step = k; },
         "show step K (frame K to K+1) instead: its first sub-step with contacts, else its start")
      ->type_name("K")
      ->check(integer_in(0, std::numeric_limits<int>::max()));
  app.add_option_function<std::string>(
         "--image-size",
         [&s](const std::string& v) {
           const std::size_t x = v.find('x');
           std::from_chars(v.data(), v.data() + x, s.image_width);
           std::from_chars(v.data() + x + 1, v.data() + v.size(), s.image_height);
         },
         "picture size in pixels, each side 16 to 4096 (default 1200x900)")
      ->type_name("WxH")
      ->check(image_size());
  app.add_option("--camera", s.camera,
                 "place the camera at EX,EY,EZ (scene units), looking at the centre of the contacts or at TX,TY,TZ "
                 "and with UX,UY,UZ up in the picture (default: automatic, from the side that shows the most contact triangles, up the axis the scene sits on)")
      ->type_name("EX,EY,EZ[,TX,TY,TZ[,UX,UY,UZ]]");
  app.add_option("--colored", s.colored,
                 "write the meshes at the same moment as one PLY with per-face colours (contact triangles red), for "
                 "MeshLab or Blender")
      ->type_name("FILE.ply");
}

void add_file_options(CLI::App& app, RunSettings& s) {
  app.add_option("--contacts", s.contacts,
                 "write every contact as CSV or JSON (by extension): frame and substep (the step from frame F to "
                 "F+1, sub-step S), kind (vf: a vertex and a face; ee: two edges), mesh_a, feature_a, mesh_b, "
                 "feature_b, v0..v3 (the vertex then the face's three, or the two vertices of each edge), toi (frame "
                 "time F + (S + t)/K) and t (local time in the sub-step); streamed as steps finish")
      ->type_name("FILE.csv|FILE.json");
  app.add_option("--stats", s.stats,
                 "write the statistics of every sub-step as JSON (contacts, earliest impact, test counts, front, "
                 "stage times) and a summary; streamed as steps finish")
      ->type_name("FILE.json");
  app.add_option_function<std::string>(
         "--partial", [&s](const std::string& v) { s.partial = v == "remove" ? Partial::Remove : Partial::Keep; },
         "when a run stops early (a frame that cannot be read, SIGINT, SIGTERM): keep (default) writes the "
         "finished steps under the final names, marked incomplete (CSV: a last line '# incomplete: REASON'; JSON: "
         "\"complete\": false, \"stopped\": REASON); remove writes no file. Either way no temporary is left")
      ->type_name("HOW")
      ->check(CLI::IsMember({"keep", "remove"}));
  app.add_flag("--exit-zero", s.exit_zero, "exit with status 0 even when collisions are found");
}

void add_engine_options(CLI::App& app, RunSettings& s) {
  add_method_option(app, s.scene.method);
  app.add_option("--substeps", s.substeps,
                 "split each step into K linear sub-steps, 1 to 1000 (default 1); times of impact stay in frame time")
      ->type_name("K")
      ->check(integer_in(1, 1000));
  add_min_distance_option(app, s.scene.min_distance, "; at most 1% of the scene's bounding-box diagonal");
  app.add_option_function<std::string>(
         "--volume", [&s](const std::string& v) { s.scene.volume = parse_volume(v.c_str()); },
         "bounding volume of the scene BVH: kdop18 (default) or aabb")
      ->type_name("NAME")
      ->check(CLI::IsMember({"kdop18", "aabb"}));
  app.add_option("--rebuild-sprout", s.scene.rebuild_sprout_ratio,
                 "rebuild the front when nodes added by sprouting exceed this fraction of it, greater than 0 to 100 "
                 "(default 0.3)")
      ->type_name("R")
      ->check(number_in(0, 100, true));
  app.add_option("--rebuild-invalid", s.scene.rebuild_invalid_ratio,
                 "rebuild the front when invalidated nodes exceed this fraction of it, greater than 0 to 100 "
                 "(default 0.45)")
      ->type_name("R")
      ->check(number_in(0, 100, true));
  add_bvh_options(app, s.scene.bvh, s.scene.leaf_size, s.scene.representatives, s.scene.self_culling);
  add_threads_option(app, s.threads);
}

}  // namespace mccd::cli
