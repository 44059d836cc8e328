// `mccd run --image` and `--colored`: the picture shows the contact triangles in red, the PLY
// colours exactly the triangles the run reports; and the cloth-ball step of the shared data
// end to end (contacts, statistics, picture).
#include <gtest/gtest.h>

#include <stb_image.h>

#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "fixtures/scenes.h"
#include "support/cli.h"
#include "support/data.h"

namespace fs = std::filesystem;
using namespace mccd::test;

namespace {

struct Png {
  int width = 0, height = 0;
  std::size_t red = 0;  ///< pixels that read as the highlight red
};

Png read_png(const std::string& path) {
  const std::string bytes = slurp(path);
  Png p;
  int channels = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()), int(bytes.size()),
                                            &p.width, &p.height, &channels, 3);
  if (!px) return p;
  for (std::size_t i = 0; i < std::size_t(p.width) * p.height; ++i) {
    const int r = px[3 * i], g = px[3 * i + 1], b = px[3 * i + 2];
    p.red += r > 150 && r > 2 * g && r > 2 * b;
  }
  stbi_image_free(px);
  return p;
}

/// Faces of a binary PLY written by mccd::write_ply with colours, counted by colour: red or not.
std::pair<std::size_t, std::size_t> ply_face_colours(const std::string& path) {
  const std::string bytes = slurp(path);
  const std::size_t end = bytes.find("end_header\n");
  if (end == std::string::npos || bytes.find("property uchar red") > end) return {0, 0};
  auto count = [&](const std::string& element) {
    const std::size_t at = bytes.find("element " + element + " ");
    return std::stoul(bytes.substr(at + 9 + element.size()));
  };
  const std::size_t nv = count("vertex"), nf = count("face");
  std::size_t at = end + 11 + 24 * nv, red = 0;
  for (std::size_t f = 0; f < nf; ++f, at += 1 + 12 + 3) {
    const auto r = static_cast<unsigned char>(bytes[at + 13]), g = static_cast<unsigned char>(bytes[at + 14]);
    red += r > 200 && g < 60;
  }
  return {red, nf - red};
}

/// The number printed before "triangles highlighted".
std::size_t highlighted(const std::string& out) {
  const std::size_t at = out.find(" triangles highlighted");
  if (at == std::string::npos) return 0;
  std::size_t b = out.rfind(", ", at) + 2;
  std::string digits;
  for (; b < at; ++b)
    if (std::isdigit(static_cast<unsigned char>(out[b]))) digits += out[b];
  return digits.empty() ? 0 : std::stoul(digits);
}

}  // namespace

TEST(CliImage, PictureAndColouredMeshOfTheFirstContact) {
  ScratchDir dir("mccd_cli_image");
  const auto scene = mccd::make_folding_cloth(16, 6);
  std::vector<mccd::Positions> frames;
  for (const auto& f : scene.frames) frames.push_back(f[0]);
  const std::string pattern = write_frames(dir.path(), "f", scene.meshes[0], frames);
  const auto r = run_cli({"run", pattern, "--image", dir.file("first.png"), "--image-size", "400x300", "--colored",
                          dir.file("first.ply")});
  ASSERT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.out.find("picture: " + dir.file("first.png") + " (step "), std::string::npos) << r.out;
  const Png png = read_png(dir.file("first.png"));
  EXPECT_EQ(png.width, 400);
  EXPECT_EQ(png.height, 300);
  EXPECT_GT(png.red, 100u) << "the contact triangles are not visible";
  const std::size_t lit = highlighted(r.out);
  EXPECT_GT(lit, 0u) << r.out;
  const auto [red, other] = ply_face_colours(dir.file("first.ply"));
  EXPECT_EQ(red, lit);
  EXPECT_EQ(red + other, scene.meshes[0].num_faces());
}

TEST(CliImage, ImageStepAndCamera) {
  ScratchDir dir("mccd_cli_image_step");
  const auto r = run_cli({"run", "--scene", "cloth", "--size", "1", "--frames", "8", "--image-step", "5", "--image",
                          dir.file("five.png"), "--image-size", "200x150", "--camera", "0,-3,2,0,0,0,0,0,1", "--quiet"});
  ASSERT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.out.find("picture: " + dir.file("five.png") + " (step 5 at frame time 5."), std::string::npos) << r.out;
  EXPECT_GT(read_png(dir.file("five.png")).red, 0u);
}

TEST(CliImage, NoContactNoRed) {
  ScratchDir dir("mccd_cli_image_none");
  mccd::TriMesh grid = mccd::make_folding_cloth(6, 2).meshes[0];
  std::vector<mccd::Positions> frames(3, grid.vertices);
  for (std::size_t v = 0; v < grid.vertices.rows(); ++v) frames[2](v, 2) += 0.2;
  const std::string pattern = write_frames(dir.path(), "calm", grid, frames);
  const auto r = run_cli({"run", pattern, "--image", dir.file("none.png"), "--image-size", "160x120"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("no contact to show: the picture is of frame 0"), std::string::npos) << r.out;
  const Png png = read_png(dir.file("none.png"));
  EXPECT_EQ(png.width, 160);
  EXPECT_EQ(png.red, 0u);
}

// The acceptance run of issue 11: the cloth-ball step of the Time-of-Impact data.
TEST(CliImage, ClothBallContactsStatisticsAndPicture) {
  const fs::path frames = data_dir() / "toi/cloth-ball/frames";
  MCCD_REQUIRE_DATA(frames);
  ScratchDir dir("mccd_cli_cloth_ball");
  const auto r = run_cli({"run", frames.string(), "--contacts", dir.file("c.csv"), "--stats", dir.file("s.json"), "--image",
                          dir.file("cb.png"), "--image-size", "600x450"});
  ASSERT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.out.find("cloth_ball92.ply .. cloth_ball93.ply: 2 frames"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 step (cloth_ball92.ply to cloth_ball93.ply), 1 with contacts: 113,854 contacts (19,032 vertex-face, 94,822 edge-edge)"), std::string::npos) << r.out;
  // issue 36: 7.49e-6 of the step, once printed as 0.0000
  EXPECT_NE(r.out.find("first impact at frame time 7.49e-6 (step 0: cloth_ball92.ply to cloth_ball93.ply)\n"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(lines_of(slurp(dir.file("c.csv"))).size(), 113854u + 1);
  const nlohmann::json s = nlohmann::json::parse(slurp(dir.file("s.json")));
  EXPECT_EQ(s["complete"], true);
  EXPECT_EQ(s["steps"][0]["vf_contacts"], 19032);
  EXPECT_EQ(s["steps"][0]["ee_contacts"], 94822);
  EXPECT_GT(read_png(dir.file("cb.png")).red, 500u);  // 1,627 of 270,000 pixels when written
  EXPECT_EQ(dir.names(), (std::vector<std::string>{"c.csv", "cb.png", "s.json"}));
}
