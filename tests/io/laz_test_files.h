// Helpers of the LAZ tests: the real LAZ files (other projects' in PARALLAX_TEST_DATA/laz, the
// ones made for Parallax in tests/data/laz; see its README), and the raw records a LAZ file decodes to, for byte-for-byte comparisons with a LAS twin or another
// decoder.
#pragma once

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "io/las_header.h"
#include "io/laz_source.h"
#include "support/file_bytes.h"
#include "support/test_data.h"

namespace parallax::test {

// `name` in tests/data/laz when it was made for Parallax, else in PARALLAX_TEST_DATA/laz (other
// projects' files; a test fails saying what to set when that folder is missing).
inline std::filesystem::path lazData(const std::string& name) {
  const std::filesystem::path own = std::filesystem::path(PARALLAX_LAZ_DATA) / name;
  if (std::filesystem::is_regular_file(own)) return own;
  return testDataFile("laz/" + name);
}

// Every record of a LAZ file, decoded chunk by chunk in file order.
inline std::string lazRecords(const std::filesystem::path& path) {
  std::unique_ptr<LazSource> source = openLazSource(openFileSource(path), readLasHeader(path));
  LazChunkDecoder decoder(*source);
  std::string out;
  const std::size_t length = source->records.record_length;
  for (std::size_t i = 0; i < source->chunks.size(); ++i) {
    const std::byte* records = decoder.decode(*source, i);
    out.append(reinterpret_cast<const char*>(records), source->chunks[i].points * length);
  }
  return out;
}

// The point records of an uncompressed LAS file, as stored.
inline std::string lasRecords(const std::filesystem::path& path) {
  const LasHeader header = readLasHeader(path);
  return fileBytes(path).substr(header.point_data_offset,
                                header.point_count * header.record_length);
}

// The first record that differs, or -1.
inline long long firstDifferentRecord(const std::string& a, const std::string& b,
                                      std::size_t length) {
  const std::size_t n = std::min(a.size(), b.size()) / length;
  for (std::size_t i = 0; i < n; ++i) {
    if (std::memcmp(a.data() + i * length, b.data() + i * length, length) != 0) {
      return (long long)i;
    }
  }
  return a.size() == b.size() ? -1 : (long long)n;
}

}  // namespace parallax::test
