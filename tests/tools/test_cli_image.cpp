// `mccd run --image` and `--colored`: the picture shows the contact triangles in red, the PLY
// colours exactly the triangles the run reports; and the cloth-ball step of the shared data
// end to end (contacts, statistics, picture).
#include <gtest/gtest.h>

#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "fixtures/scenes.h"
#include "support/cli.h"
#include "support/data.h"
#include "support/picture.h"

namespace fs = std::filesystem;
using namespace mccd::test;
using mccd::cli::Rgb8;

namespace {

struct Png {
  int width = 0, height = 0;
  std::size_t red = 0;  ///< pixels that read as the highlight red
};

/// A picture (PNG or JPEG) and its red pixels.
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

/// The frame time printed in "picture: FILE (step K at frame time T, ...".
std::string picture_time(const std::string& out) {
  const std::size_t at = out.find(" at frame time ", out.find("picture: "));
  if (at == std::string::npos) return "";
  return out.substr(at + 15, out.find(',', at) - at - 15);
}

/// Whether pixel `p` is a shade of `c` (flat shading scales a colour by about 0.1 to 1.05),
/// within JPEG-free rounding.
bool shade_of(Rgb8 p, Rgb8 c) {
  const double dot = double(p.r) * c.r + double(p.g) * c.g + double(p.b) * c.b;
  const double norm = double(c.r) * c.r + double(c.g) * c.g + double(c.b) * c.b;
  const double k = norm > 0 ? dot / norm : 0;
  if (k < 0.08 || k > 1.1) return false;
  return std::abs(p.r - k * c.r) <= 6 && std::abs(p.g - k * c.g) <= 6 && std::abs(p.b - k * c.b) <= 6;
}

/// The background: light grey, a little bluer at the bottom.
bool background(Rgb8 p) { return p.r >= 200 && p.r == p.g && p.b >= p.r && p.b <= p.r + 4; }

}  // namespace

// Issue 36: the picture says what it shows (scene, step and its frame time, contacts) and
// what its colours mean, in the picture itself.
TEST(CliImage, CaptionAndLegendInThePicture) {
  ScratchDir here("mccd_cli_key");
  const auto r = run_cli({"demo", "--image-size", "800x600"}, here.path());
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string time = picture_time(r.out);
  ASSERT_FALSE(time.empty()) << r.out;
  const mccd::cli::Image img = read_picture(here.file("demo.png"));
  ASSERT_EQ(img.width, 800);
  const ReadKey key = read_key(img);
  ASSERT_GT(key.height, 0) << "no key at the top of the picture";
  EXPECT_LT(key.height, 600 * 2 / 5);
  std::string text;
  for (const std::string& row : key.rows) text += row + "\n";
  EXPECT_EQ(text.find('\x1a'), std::string::npos) << "cells that read as no glyph:\n" << text;
  // the caption: the scene, the step the demo draws (44 * 2 / 5) and its frame time, the contacts
  EXPECT_EQ(key.rows[0], "demo: a cloth dropped onto a ball") << text;
  EXPECT_NE(text.find("step 17 (frame 17 to 18) at frame time " + time + "\n"), std::string::npos) << text;
  EXPECT_NE(r.out.find("picture: demo.png (step 17 at frame time " + time + ", "), std::string::npos) << r.out;
  EXPECT_NE(text.find("contacts shown: "), std::string::npos) << text;
  EXPECT_NE(text.find(" triangles highlighted"), std::string::npos) << text;
  // the legend: the highlight red, and the two meshes by name
  EXPECT_EQ(swatch_before(key, "triangles of the contacts shown"), (Rgb8{229, 31, 20})) << text;
  EXPECT_TRUE(swatch_before(key, "cloth")) << text;
  EXPECT_TRUE(swatch_before(key, "ball")) << text;
  EXPECT_TRUE(swatch_before(key, "outline (a jump in depth)")) << text;
  // Flat shading draws a triangle's inside in one colour: every such pixel of the scene (all
  // eight neighbours the same) is the background or a shade of a legend colour, and every
  // legend colour (but the outline, a darker shade) has pixels of its own.
  std::vector<Rgb8> legend;
  for (const auto& row : key.swatches)
    for (const auto& c : row)
      if (c && std::find(legend.begin(), legend.end(), *c) == legend.end()) legend.push_back(*c);
  ASSERT_GE(legend.size(), 5u) << text;  // highlight, seen through cloth and ball, cloth, ball, outline
  std::size_t inside = 0, explained = 0;
  std::vector<std::size_t> own(legend.size(), 0);
  for (int y = key.height + 1; y + 1 < img.height; ++y)
    for (int x = 1; x + 1 < img.width; ++x) {
      const Rgb8 p = img.at(x, y);
      bool flat = !background(p);
      for (int dy = -1; dy <= 1 && flat; ++dy)
        for (int dx = -1; dx <= 1 && flat; ++dx) flat = img.at(x + dx, y + dy) == p;
      if (!flat) continue;
      ++inside;
      std::size_t matches = 0, which = 0;
      for (std::size_t i = 0; i < legend.size(); ++i)
        if (shade_of(p, legend[i])) ++matches, which = i;
      explained += matches > 0;
      if (matches == 1) ++own[which];
    }
  ASSERT_GT(inside, 10000u);
  EXPECT_GT(double(explained), 0.995 * double(inside)) << explained << " of " << inside;
  for (std::size_t i = 0; i < legend.size(); ++i) {
    const bool darker_shade = std::any_of(legend.begin(), legend.end(),
                                          [&](Rgb8 c) { return !(c == legend[i]) && shade_of(legend[i], c); });
    if (!darker_shade) {
      EXPECT_GT(own[i], 0u) << "legend colour " << int(legend[i].r) << "," << int(legend[i].g) << ","
                            << int(legend[i].b) << " not in the picture";
    }
  }
}

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
  // 200 pixels wide: too narrow for a caption, and the picture line says so
  EXPECT_NE(r.out.find("; no caption or legend: too small for them)\n"), std::string::npos) << r.out;
  EXPECT_EQ(read_key(read_picture(dir.file("five.png"))).height, 0);
}

// Issue 36: --image writes the format its extension names (case ignored), or refuses it with
// status 2 before any step.
TEST(CliImage, FormatByExtension) {
  ScratchDir dir("mccd_cli_formats");
  const std::vector<std::string> base{"run",          "--scene",   "cloth",   "--size", "1", "--frames", "6",
                                      "--image-size", "320x240", "--quiet", "--image"};
  for (const std::string name : {"p.jpg", "q.JPEG", "r.png"}) {
    std::vector<std::string> args = base;
    args.push_back(dir.file(name));
    const auto r = run_cli(args);
    EXPECT_EQ(r.status, 1) << r.err;
    const std::string bytes = slurp(dir.file(name));
    if (name == "r.png") {
      EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << name;
    } else {
      EXPECT_EQ(bytes.substr(0, 3), "\xFF\xD8\xFF") << name;  // a JPEG's start-of-image marker
    }
    const mccd::cli::Image img = read_picture(dir.file(name));
    EXPECT_EQ(img.width, 320) << name;
    EXPECT_EQ(img.height, 240) << name;
    EXPECT_GT(read_png(dir.file(name)).red, 50u) << name;
  }
  for (const std::string name : {"s.bmp", "t.gif", "noext", "u.png.txt"}) {
    std::vector<std::string> args = base;
    args.push_back(dir.file(name));
    const auto r = run_cli(args);
    EXPECT_EQ(r.status, 2) << name;
    EXPECT_EQ(r.err, "mccd run: error: --image " + dir.file(name) +
                         ": expected a .png (PNG) or .jpg / .jpeg (JPEG) file name\n");
    EXPECT_EQ(r.out, "") << name;  // refused before the first step
  }
  // the coloured mesh is a PLY, and only a .ply name is taken for it
  const auto r = run_cli({"run", "--scene", "cloth", "--size", "1", "--frames", "6", "--colored", dir.file("m.obj")});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "mccd run: error: --colored " + dir.file("m.obj") + ": expected a .ply file name\n");
  EXPECT_EQ(dir.names(), (std::vector<std::string>{"p.jpg", "q.JPEG", "r.png"}));
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
