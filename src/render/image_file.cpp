#include "render/image_file.h"

// Debian's libstb is a compiled library: include the declarations only, never an
// STB_*_IMPLEMENTATION.
#include <stb_image.h>
#include <stb_image_write.h>

#include <cstring>
#include <stdexcept>

namespace parallax {

void writePng(const std::filesystem::path& path, const RgbaImage& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != std::size_t(image.width) * std::size_t(image.height) * 4) {
    throw std::runtime_error("writePng: the image has no pixels or a wrong pixel count");
  }
  if (!stbi_write_png(path.c_str(), image.width, image.height, 4, image.pixels.data(),
                      image.width * 4)) {
    throw std::runtime_error("cannot write the PNG file " + path.string() +
                             " (does its folder exist, is it writable?)");
  }
}

RgbaImage readPng(const std::filesystem::path& path) {
  int width = 0, height = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &width, &height, &channels, 4);
  if (!data) {
    throw std::runtime_error("cannot read the image " + path.string() + ": " +
                             stbi_failure_reason());
  }
  RgbaImage image{width, height, {}};
  image.pixels.assign(data, data + std::size_t(width) * std::size_t(height) * 4);
  stbi_image_free(data);
  return image;
}

}  // namespace parallax
