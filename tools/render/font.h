#pragma once
/// @file The bitmap font of the `mccd` pictures' captions and legends: printable ASCII (32 to
/// 126), each glyph 5 dots wide and 8 high (capitals and digits in rows 0 to 6, descenders
/// in row 7), drawn in cells of 6 x 10 dots (one dot between letters, two between lines).
/// Each dot is drawn as a square of pixels (the scale).
#include <array>
#include <cstdint>

namespace mccd::cli::font {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 8;  ///< dots
inline constexpr int kCellWidth = 6, kCellHeight = 10;   ///< dots: the advance and the line pitch

/// One glyph: a row of dots per byte, top row first; bit 4 is the left column, bit 0 the right.
using Glyph = std::array<std::uint8_t, kGlyphHeight>;

/// The glyph of `c`; characters outside 32 to 126 get the glyph of '?'.
const Glyph& glyph(char c);

/// Whether dot (column x, row y) of `g` is inked; 0 <= x < kGlyphWidth, 0 <= y < kGlyphHeight.
constexpr bool inked(const Glyph& g, int x, int y) { return (g[std::size_t(y)] >> (kGlyphWidth - 1 - x)) & 1; }

}  // namespace mccd::cli::font
