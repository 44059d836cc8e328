#pragma once
/// @file The key of a `mccd` picture: a band across the top with a caption (what is shown:
/// the scene, the step and its frame time, the contacts) and a legend (a swatch of every
/// colour the picture uses, and what it means), in the built-in bitmap font (render/font.h).
///
/// The band is a grid of text cells. With s = key_scale() pixels per font dot, the cell in
/// row r and column c has its top-left pixel at (kKeyPad * s + c * 6 * s, kKeyPad * s +
/// r * 10 * s); a glyph's dots are kKeyInk on kKeyPaper; a legend swatch fills the glyph
/// boxes (5 x 8 dots) of two neighbouring cells, and the dot between them, with its colour.
/// Caption lines come first, broken at spaces (runs of spaces read as one; a word longer than
/// a row is cut); the legend's items follow side by side, each a
/// swatch per colour (a blank cell between swatches), a blank cell and its label. The band
/// ends with a rule of kKeyRule one dot high.
#include <optional>
#include <string>
#include <vector>

#include "render/image.h"

namespace mccd::cli {

/// One legend entry: the colours it explains and what they mean.
struct LegendItem {
  std::vector<Rgb8> swatches;
  std::string label;
};

/// What a picture's key says.
struct PictureKey {
  std::vector<std::string> caption;  ///< lines, broken further at spaces to fit
  std::vector<LegendItem> legend;
};

inline constexpr Rgb8 kKeyPaper{255, 255, 255}, kKeyInk{24, 24, 24}, kKeyRule{150, 150, 150};
/// Dots of paper around the text grid.
inline constexpr int kKeyPad = 3;
/// Fewest text columns a key is drawn with: narrower pictures have none.
inline constexpr int kKeyMinColumns = 40;

/// Pixels per font dot in a width x height picture: 1 up to 999 x 749, 2 from 1000 x 750
/// (the default 1200 x 900), at most 4.
int key_scale(int width, int height);
/// Text columns of the grid in a picture `width` wide at `scale`.
int key_columns(int width, int scale);

/// One cell of the grid: a character, or a swatch's half.
struct KeyCell {
  char c = ' ';
  std::optional<Rgb8> swatch;
};
/// The key laid out in rows of at most `columns` cells (rows carry no trailing blanks).
std::vector<std::vector<KeyCell>> layout_key(const PictureKey& key, int columns);

/// Height in pixels of the band `key` takes at the top of a width x height picture: 0 when
/// it has fewer than kKeyMinColumns columns or the band would take more than 2/5 of it.
int key_height(const PictureKey& key, int width, int height);

/// Draws `key` into the top `height` rows of `image`, across its width: paper, the rule in
/// the last dot, the text rows that fit above it. `height` is normally key_height() (or that
/// of a key with more rows, drawn with this one's); nothing is drawn when it is 0.
void draw_key(Image& image, const PictureKey& key, int height);

}  // namespace mccd::cli
