#include "render/image.h"

#include <stb_image_write.h>

#include <mccd/geometry/atomic_file.h>
#include <mccd/geometry/error.h>

namespace mccd::cli {

namespace {
void append(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
}
}  // namespace

void write_png(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != 3 * std::size_t(image.width) * std::size_t(image.height))
    throw Error(path + ": cannot write an empty or malformed image");
  std::string bytes;
  if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.rgb.data(), 3 * image.width))
    throw Error(path + ": PNG encoding failed");
  write_atomically(path, bytes);
}

}  // namespace mccd::cli
