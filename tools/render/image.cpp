#include "render/image.h"

#include <stb_image_write.h>

#include <algorithm>
#include <cctype>
#include <filesystem>

#include <mccd/geometry/atomic_file.h>
#include <mccd/geometry/error.h>

namespace mccd::cli {

namespace {

constexpr int kJpegQuality = 90;

void append(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}

}  // namespace

void Image::fill(int x0, int y0, int x1, int y1, Rgb8 c) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, width), y1 = std::min(y1, height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) set(x, y, c);
}

ImageFormat image_format(const std::string& option, const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".png") return ImageFormat::Png;
  if (ext == ".jpg" || ext == ".jpeg") return ImageFormat::Jpeg;
  throw Error(option + " " + path + ": expected a .png (PNG) or .jpg / .jpeg (JPEG) file name");
}

void write_image(const std::string& path, const Image& image) {
  const ImageFormat format = image_format("--image", path);
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != 3 * std::size_t(image.width) * std::size_t(image.height))
    throw Error(path + ": cannot write an empty or malformed image");
  std::string bytes;
  const bool ok = format == ImageFormat::Png
                      ? stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.rgb.data(),
                                               3 * image.width) != 0
                      : stbi_write_jpg_to_func(append, &bytes, image.width, image.height, 3, image.rgb.data(),
                                               kJpegQuality) != 0;
  if (!ok) throw Error(path + (format == ImageFormat::Png ? ": PNG" : ": JPEG") + " encoding failed");
  write_atomically(path, bytes);
}

}  // namespace mccd::cli
