#include "support/picture.h"

#include <stb_image.h>

#include "render/font.h"
#include "render/key.h"
#include "support/cli.h"

namespace mccd::test {

using cli::Image;
using cli::Rgb8;

Image read_picture(const std::string& path) {
  const std::string bytes = slurp(path);
  Image img;
  int channels = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()), int(bytes.size()),
                                            &img.width, &img.height, &channels, 3);
  if (!px) return {};
  img.rgb.assign(px, px + 3 * std::size_t(img.width) * std::size_t(img.height));
  stbi_image_free(px);
  return img;
}

namespace {

/// The cell at (row r, column c) of the key's grid: a character, a swatch ('\x7f' and its
/// colour) or '\x1a' for anything else.
char read_cell(const Image& img, int s, int r, int c, std::optional<Rgb8>& swatch) {
  namespace font = cli::font;
  const int x0 = (cli::kKeyPad + c * font::kCellWidth) * s, y0 = (cli::kKeyPad + r * font::kCellHeight) * s;
  font::Glyph bits{};
  std::optional<Rgb8> other;
  bool mixed = false, ink = false;
  for (int y = 0; y < font::kGlyphHeight; ++y)
    for (int x = 0; x < font::kGlyphWidth; ++x) {
      const Rgb8 p = img.at(x0 + x * s + s / 2, y0 + y * s + s / 2);
      if (p == cli::kKeyInk) {
        bits[std::size_t(y)] = std::uint8_t(bits[std::size_t(y)] | 1 << (font::kGlyphWidth - 1 - x));
        ink = true;
      } else if (!(p == cli::kKeyPaper)) {
        if (other && !(*other == p)) mixed = true;
        other = p;
      }
    }
  if (other) {
    // a swatch fills the whole glyph box with one colour
    bool full = !mixed && !ink;
    for (int y = 0; full && y < font::kGlyphHeight; ++y)
      for (int x = 0; full && x < font::kGlyphWidth; ++x)
        full = img.at(x0 + x * s + s / 2, y0 + y * s + s / 2) == *other;
    if (!full) return '\x1a';
    swatch = other;
    return '\x7f';
  }
  for (int ch = 32; ch < 127; ++ch)
    if (font::glyph(char(ch)) == bits) return char(ch);
  return '\x1a';
}

}  // namespace

ReadKey read_key(const Image& img) {
  ReadKey key;
  if (img.width <= 0 || img.height <= 0) return key;
  // the band: paper down the left edge, then the rule
  int y = 0;
  while (y < img.height && img.at(0, y) == cli::kKeyPaper) ++y;
  const int s = cli::key_scale(img.width, img.height);
  if (y == 0 || y + s > img.height) return key;
  for (int k = 0; k < s; ++k)
    if (!(img.at(0, y + k) == cli::kKeyRule)) return key;
  key.height = y + s;
  const int columns = cli::key_columns(img.width, s);
  for (int r = 0; (cli::kKeyPad + (r + 1) * cli::font::kCellHeight) * s <= key.height; ++r) {
    std::string row;
    std::vector<std::optional<Rgb8>> swatches;
    for (int c = 0; c < columns; ++c) {
      std::optional<Rgb8> sw;
      row.push_back(read_cell(img, s, r, c, sw));
      swatches.push_back(sw);
    }
    const std::size_t end = row.find_last_not_of(' ') + 1;
    row.resize(end);
    swatches.resize(end);
    key.rows.push_back(row);
    key.swatches.push_back(swatches);
  }
  while (!key.rows.empty() && key.rows.back().empty()) key.rows.pop_back(), key.swatches.pop_back();
  return key;
}

std::optional<Rgb8> swatch_before(const ReadKey& key, const std::string& label) {
  for (std::size_t r = 0; r < key.rows.size(); ++r) {
    const std::size_t at = key.rows[r].find(label);
    if (at == std::string::npos || at < 2) continue;
    if (key.rows[r][at - 1] == ' ' && key.rows[r][at - 2] == '\x7f') return key.swatches[r][at - 2];
  }
  return std::nullopt;
}

}  // namespace mccd::test
