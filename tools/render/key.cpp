#include "render/key.h"

#include <algorithm>

#include "render/font.h"

namespace mccd::cli {

namespace {

/// `line` broken at spaces into pieces of at most `columns` characters (a longer word cut),
/// runs of spaces read as one.
std::vector<std::string> wrap(const std::string& line, int columns) {
  std::vector<std::string> out;
  std::string cur;
  std::size_t at = 0;
  const std::size_t width = std::size_t(columns);
  while (at < line.size()) {
    std::size_t end = line.find(' ', at);
    if (end == std::string::npos) end = line.size();
    std::string word = line.substr(at, end - at);
    at = end + 1;
    if (word.empty()) continue;  // runs of spaces read as one
    if (!cur.empty() && cur.size() + 1 + word.size() > width) {
      out.push_back(cur);
      cur.clear();
    }
    while (word.size() > width) {
      if (!cur.empty()) out.push_back(cur), cur.clear();
      out.push_back(word.substr(0, width));
      word.erase(0, width);
    }
    cur += (cur.empty() ? "" : " ") + word;
  }
  if (!cur.empty() || out.empty()) out.push_back(cur);
  return out;
}

std::vector<KeyCell> text_cells(const std::string& s) {
  std::vector<KeyCell> out;
  for (char c : s) out.push_back({c, std::nullopt});
  return out;
}

}  // namespace

int key_scale(int width, int height) { return std::clamp(std::min(width / 500, height / 375), 1, 4); }

int key_columns(int width, int scale) {
  return std::max(0, (width / scale - 2 * kKeyPad + 1) / font::kCellWidth);
}

std::vector<std::vector<KeyCell>> layout_key(const PictureKey& key, int columns) {
  std::vector<std::vector<KeyCell>> rows;
  if (columns <= 0) return rows;
  for (const std::string& line : key.caption)
    for (const std::string& piece : wrap(line, columns)) rows.push_back(text_cells(piece));
  std::vector<KeyCell> row;
  for (const LegendItem& item : key.legend) {
    std::vector<KeyCell> cells;
    for (const Rgb8& c : item.swatches) {
      if (!cells.empty()) cells.push_back({});
      cells.push_back({' ', c});
      cells.push_back({' ', c});
    }
    if (!cells.empty()) cells.push_back({});
    const std::size_t room = std::size_t(columns) > cells.size() ? std::size_t(columns) - cells.size() : 0;
    const std::vector<KeyCell> label = text_cells(item.label.substr(0, room));
    cells.insert(cells.end(), label.begin(), label.end());
    if (cells.size() > std::size_t(columns)) cells.resize(std::size_t(columns));
    if (!row.empty() && row.size() + 3 + cells.size() > std::size_t(columns)) {
      rows.push_back(row);
      row.clear();
    }
    if (!row.empty()) row.insert(row.end(), 3, KeyCell{});
    row.insert(row.end(), cells.begin(), cells.end());
  }
  if (!row.empty()) rows.push_back(row);
  return rows;
}

int key_height(const PictureKey& key, int width, int height) {
  const int s = key_scale(width, height);
  const int columns = key_columns(width, s);
  if (columns < kKeyMinColumns) return 0;
  const int rows = int(layout_key(key, columns).size());
  if (rows == 0) return 0;
  const int h = (2 * kKeyPad + rows * font::kCellHeight) * s;
  return 5 * h > 2 * height ? 0 : h;
}

void draw_key(Image& image, const PictureKey& key, int h) {
  if (h <= 0) return;
  const int s = key_scale(image.width, image.height);
  image.fill(0, 0, image.width, h - s, kKeyPaper);
  image.fill(0, h - s, image.width, h, kKeyRule);
  const std::vector<std::vector<KeyCell>> rows = layout_key(key, key_columns(image.width, s));
  const std::size_t fit = std::size_t(std::max(0, (h / s - 2 * kKeyPad) / font::kCellHeight));
  for (std::size_t r = 0; r < std::min(rows.size(), fit); ++r)
    for (std::size_t c = 0; c < rows[r].size(); ++c) {
      const KeyCell& cell = rows[r][c];
      const int x0 = (kKeyPad + int(c) * font::kCellWidth) * s, y0 = (kKeyPad + int(r) * font::kCellHeight) * s;
      if (cell.swatch) {
        // the glyph box, and the dot to the right when the next cell is the swatch's other half
        const bool joined = c + 1 < rows[r].size() && rows[r][c + 1].swatch == cell.swatch;
        image.fill(x0, y0, x0 + (font::kGlyphWidth + joined) * s, y0 + font::kGlyphHeight * s, *cell.swatch);
        continue;
      }
      const font::Glyph& g = font::glyph(cell.c);
      for (int y = 0; y < font::kGlyphHeight; ++y)
        for (int x = 0; x < font::kGlyphWidth; ++x)
          if (font::inked(g, x, y)) image.fill(x0 + x * s, y0 + y * s, x0 + (x + 1) * s, y0 + (y + 1) * s, kKeyInk);
    }
}

}  // namespace mccd::cli
