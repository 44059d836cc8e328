#pragma once
/// @file Pictures written by `mccd` read back in tests: the pixels (PNG or JPEG, stb_image),
/// and the key across their top (tools/render/key.h) read back as text, cell by cell, against
/// the built-in font: what a person would read in the caption and the legend.
#include <optional>
#include <string>
#include <vector>

#include "render/image.h"

namespace mccd::test {

/// The picture in `path` as RGB (an empty image when it cannot be read).
cli::Image read_picture(const std::string& path);

/// A picture's key as read back.
struct ReadKey {
  int height = 0;                 ///< pixels from the top to the end of the rule (0: no key)
  std::vector<std::string> rows;  ///< one string per text row: swatch cells as '\x7f', cells
                                  ///< that match no glyph as '\x1a'; trailing blanks dropped
  std::vector<std::vector<std::optional<cli::Rgb8>>> swatches;  ///< per row and cell: the swatch's colour
};

/// Reads the key drawn by cli::draw_key at the top of `image` (exact colours: a PNG).
ReadKey read_key(const cli::Image& image);

/// The colour of the swatch cells just before `label` in `key` (the legend item's last
/// swatch), if `label` follows a swatch there.
std::optional<cli::Rgb8> swatch_before(const ReadKey& key, const std::string& label);

}  // namespace mccd::test
