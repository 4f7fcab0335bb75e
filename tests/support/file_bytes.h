// A file's bytes as a string (empty when it cannot be read): what tests compare outputs with.
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace parallax::test {

inline std::string fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace parallax::test
