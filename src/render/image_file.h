// PNG files of rendered frames (and golden images in tests), through Debian's compiled libstb.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace parallax {

// An 8-bit RGBA image, rows top first, no padding.
struct RgbaImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // width * height * 4
};

// Throws std::runtime_error naming the path when the file cannot be written.
void writePng(const std::filesystem::path& path, const RgbaImage& image);
// Throws std::runtime_error naming the path and stb's reason when the file cannot be read.
RgbaImage readPng(const std::filesystem::path& path);

}  // namespace parallax
