// The key of `mccd` pictures (tools/render/key.h) and its bitmap font (tools/render/font.h):
// every glyph distinct and on its baseline, the caption broken at spaces to the picture's
// width, and a key drawn into an image read back, cell by cell, as the text and colours given.
#include "render/key.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "render/font.h"
#include "support/picture.h"

namespace font = mccd::cli::font;
using mccd::cli::Image;
using mccd::cli::PictureKey;
using mccd::cli::Rgb8;

namespace {

bool any_ink(const font::Glyph& g, int row) { return g[std::size_t(row)] != 0; }

std::string printable() {
  std::string s;
  for (int c = 32; c < 127; ++c) s.push_back(char(c));
  return s;
}

Image blank(int w, int h) { return Image{w, h, std::vector<std::uint8_t>(3 * std::size_t(w) * std::size_t(h), 90)}; }

}  // namespace

TEST(PictureFont, EveryGlyphDistinctAndOnItsBaseline) {
  std::set<font::Glyph> seen;
  std::string descenders;
  for (const char c : printable()) {
    const font::Glyph& g = font::glyph(c);
    EXPECT_TRUE(seen.insert(g).second) << "glyph of '" << c << "' drawn like another";
    bool ink = false;
    for (int y = 0; y < font::kGlyphHeight; ++y) ink = ink || any_ink(g, y);
    EXPECT_EQ(ink, c != ' ') << "'" << c << "'";
    if (any_ink(g, font::kGlyphHeight - 1)) descenders.push_back(c);
    // capitals and digits stand on row 6 and reach row 0
    if (std::isupper(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c))) {
      EXPECT_TRUE(any_ink(g, 0) && any_ink(g, 6)) << "'" << c << "'";
      EXPECT_FALSE(any_ink(g, 7)) << "'" << c << "'";
    }
  }
  EXPECT_EQ(descenders, ",_gjpqy");
  EXPECT_EQ(font::glyph('\x01'), font::glyph('?'));
  EXPECT_EQ(font::glyph('\xe9'), font::glyph('?'));
}

TEST(PictureKey, ScaleColumnsAndRoom) {
  EXPECT_EQ(mccd::cli::key_scale(320, 240), 1);
  EXPECT_EQ(mccd::cli::key_scale(1200, 900), 2);
  EXPECT_EQ(mccd::cli::key_scale(4096, 2048), 4);
  EXPECT_EQ(mccd::cli::key_columns(320, 1), 52);  // (320 - 6 + 1) / 6
  EXPECT_EQ(mccd::cli::key_columns(1200, 2), 99);  // (600 - 6 + 1) / 6
  const PictureKey key{{"a caption"}, {{{Rgb8{200, 0, 0}}, "red"}}};
  EXPECT_EQ(mccd::cli::key_height(key, 200, 150), 0);  // 32 columns: too narrow for a key
  EXPECT_EQ(mccd::cli::key_height(key, 320, 240), (2 * 3 + 2 * 10) * 1);
  EXPECT_EQ(mccd::cli::key_height(key, 1200, 900), (2 * 3 + 2 * 10) * 2);
  // more rows than two fifths of the height: no key
  const PictureKey tall{std::vector<std::string>(12, "line"), {}};
  EXPECT_EQ(mccd::cli::key_height(tall, 320, 240), 0);
}

TEST(PictureKey, CaptionBrokenAtSpacesToTheWidth) {
  const std::string line =
      "step 17 (cloth_ball92.ply to cloth_ball93.ply) at frame time 7.49e-6,  and a word longer than any row: "
      "abcdefghijklmnopqrstuvwxyzabcdefghijklmnopqrstuvwxyz";
  const auto rows = mccd::cli::layout_key(PictureKey{{line, "short"}, {}}, 40);
  std::vector<std::string> text;
  for (const auto& row : rows) {
    text.emplace_back();
    for (const auto& cell : row) text.back().push_back(cell.c);
  }
  EXPECT_EQ(text, (std::vector<std::string>{"step 17 (cloth_ball92.ply to",
                                            "cloth_ball93.ply) at frame time 7.49e-6,",  // 40 columns
                                            "and a word longer than any row:",
                                            "abcdefghijklmnopqrstuvwxyzabcdefghijklmn", "opqrstuvwxyz", "short"}));
}

TEST(PictureKey, DrawnKeyReadsBackAsItsTextAndColours) {
  Image img = blank(640, 480);
  const Rgb8 red{230, 31, 20}, blue{184, 199, 219}, tan{219, 204, 163};
  const PictureKey key{{"every printable character: " + printable(), "second line"},
                       {{{red}, "triangles of the contacts shown"},
                        {{blue, tan}, "the same, behind a surface"},
                        {{tan}, "ball"}}};
  const int h = mccd::cli::key_height(key, img.width, img.height);
  ASSERT_GT(h, 0);
  mccd::cli::draw_key(img, key, h);
  const mccd::test::ReadKey read = mccd::test::read_key(img);
  EXPECT_EQ(read.height, h);
  const auto layout = mccd::cli::layout_key(key, mccd::cli::key_columns(img.width, 1));
  ASSERT_EQ(read.rows.size(), layout.size());
  for (std::size_t r = 0; r < layout.size(); ++r) {
    std::string expected;
    for (const auto& cell : layout[r]) expected.push_back(cell.swatch ? '\x7f' : cell.c);
    EXPECT_EQ(read.rows[r], expected) << r;
  }
  ASSERT_GE(read.rows.size(), 3u);
  // the first line, 121 characters in 106 columns, broken at its last space
  EXPECT_EQ(read.rows[0], "every printable character:");
  EXPECT_EQ(read.rows[1], printable().substr(1));
  EXPECT_EQ(read.rows[2], "second line");
  EXPECT_EQ(mccd::test::swatch_before(read, "triangles of the contacts shown"), red);
  EXPECT_EQ(mccd::test::swatch_before(read, "the same, behind a surface"), tan);
  EXPECT_EQ(mccd::test::swatch_before(read, "ball"), tan);
  // below the key the image is untouched
  EXPECT_EQ(img.at(5, h), (Rgb8{90, 90, 90}));
  EXPECT_EQ(img.at(639, 479), (Rgb8{90, 90, 90}));
}
