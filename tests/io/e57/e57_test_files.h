// Helpers of the E57 tests: the PDAL test files' folder, an independent CRC-32C, and edits of a
// file's logical bytes that keep (or break) its page checksums.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>

namespace parallax::test {

// PDAL's E57 files, read from ../shared/data beside the repository (never copied into it).
inline std::filesystem::path e57DataFile(const char* name) {
  return std::filesystem::path(PARALLAX_FORMATS_DATA) / "e57" / name;
}

inline std::string readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// CRC-32C bit by bit, straight from the polynomial (0x1EDC6F41, reflected: 0x82F63B78): an
// oracle for the library's table and SSE 4.2 versions.
inline std::uint32_t slowCrc32c(std::string_view bytes) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char byte : bytes) {
    crc ^= byte;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0x82F63B78u & (0u - (crc & 1u)));
  }
  return ~crc;
}

// Rewrites the checksum of every page of `file` (stored big endian after its 1020 bytes).
inline void resealPages(std::string& file) {
  for (std::size_t page = 0; page + 1024 <= file.size(); page += 1024) {
    const std::uint32_t crc = slowCrc32c(std::string_view(file).substr(page, 1020));
    for (int i = 0; i < 4; ++i) file[page + 1020 + std::size_t(i)] = char(crc >> (24 - 8 * i));
  }
}

// Replaces the first `from` in the file's bytes with `to` (same length) and reseals the pages:
// an edit of the XML that only the XML parser can notice. False when `from` is not found.
inline bool replaceSealed(std::string& file, std::string_view from, std::string_view to) {
  const std::size_t at = file.find(from);
  if (at == std::string::npos || from.size() != to.size()) return false;
  file.replace(at, to.size(), to);
  resealPages(file);
  return true;
}

}  // namespace parallax::test
