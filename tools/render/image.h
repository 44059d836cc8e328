#pragma once
/// @file Images of the `mccd` renderer and their PNG files.
#include <cstdint>
#include <string>
#include <vector>

namespace mccd::cli {

/// An 8-bit RGB image, rows from top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< 3 * width * height bytes
};

/// Encodes `image` as PNG (stb_image_write) and writes it atomically (a temporary renamed at
/// the end). Throws mccd::Error naming the path on failure; nothing is left behind then.
void write_png(const std::string& path, const Image& image);

}  // namespace mccd::cli
