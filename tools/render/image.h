#pragma once
/// @file Images of the `mccd` renderer and their files: PNG or JPEG, by the file's extension.
#include <cstdint>
#include <string>
#include <vector>

namespace mccd::cli {

/// An 8-bit RGB colour.
struct Rgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb8&, const Rgb8&) = default;
};

/// An 8-bit RGB image, rows from top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< 3 * width * height bytes

  Rgb8 at(int x, int y) const {
    const std::size_t i = 3 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
  void set(int x, int y, Rgb8 c) {
    const std::size_t i = 3 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
    rgb[i] = c.r, rgb[i + 1] = c.g, rgb[i + 2] = c.b;
  }
  /// Fills the rectangle [x0, x1) x [y0, y1), clipped to the image.
  void fill(int x0, int y0, int x1, int y1, Rgb8 c);
};

/// The picture formats `--image` writes, by extension (case ignored): ".png" PNG; ".jpg" and
/// ".jpeg" JPEG (quality 90).
enum class ImageFormat { Png, Jpeg };

/// The format `path` names by its extension; throws mccd::Error naming `option`, the path
/// and the accepted extensions when it names none of them.
ImageFormat image_format(const std::string& option, const std::string& path);

/// Encodes `image` in the format `path`'s extension names (image_format(), stb_image_write)
/// and writes it atomically (a temporary renamed at the end). Throws mccd::Error naming the
/// path on failure; nothing is left behind then.
void write_image(const std::string& path, const Image& image);

}  // namespace mccd::cli
