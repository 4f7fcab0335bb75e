// Just enough of a LAZ file for the codec tests: the LAS header fields that locate the points,
// the "laszip encoded" VLR and the chunk table (LAS 1.4 R15 section 2; LAZ 1.4 specification).
// Test code: it trusts the file (the real LAZ reader checks everything), but stops with a test
// failure rather than reading out of bounds.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <span>
#include <string>
#include <vector>

#include "io/laz/arithmetic_decoder.h"
#include "io/laz/chunk_codec.h"
#include "io/laz/integer_codec.h"

namespace parallax::laz::testing {

struct LazTestChunk {
  std::uint64_t offset = 0;  // in the file
  std::uint64_t bytes = 0;
  std::uint64_t points = 0;
};

struct LazTestFile {
  std::vector<std::uint8_t> data;
  std::uint8_t point_format = 0;
  std::uint16_t record_length = 0;
  std::uint64_t point_count = 0;
  std::uint64_t point_data_offset = 0;
  LaszipVlr vlr;
  std::vector<LazTestChunk> chunks;

  std::span<const std::byte> chunkBytes(const LazTestChunk& c) const {
    return std::as_bytes(std::span(data)).subspan(c.offset, c.bytes);
  }
};

template <class T>
T readLE(const std::vector<std::uint8_t>& data, std::uint64_t at) {
  T v{};
  if (at + sizeof(T) > data.size()) {
    ADD_FAILURE() << "read past the end of the test file at " << at;
    return v;
  }
  std::memcpy(&v, data.data() + at, sizeof(T));
  return v;
}

inline LazTestFile readLazTestFile(const std::string& path) {
  LazTestFile f;
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << "cannot open " << path;
  f.data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (f.data.size() < 227) {
    ADD_FAILURE() << path << " is too short for a LAS header";
    return f;
  }
  const auto& d = f.data;
  const auto header_size = readLE<std::uint16_t>(d, 94);
  f.point_data_offset = readLE<std::uint32_t>(d, 96);
  const auto vlr_count = readLE<std::uint32_t>(d, 100);
  f.point_format = readLE<std::uint8_t>(d, 104) & 0x3F;  // bit 7: compressed
  f.record_length = readLE<std::uint16_t>(d, 105);
  f.point_count = readLE<std::uint32_t>(d, 107);
  if (d[25] >= 4 && f.point_count == 0) f.point_count = readLE<std::uint64_t>(d, 247);

  // The "laszip encoded" VLR.
  std::uint64_t at = header_size;
  bool found = false;
  for (std::uint32_t i = 0; i < vlr_count; ++i) {
    const std::string user(reinterpret_cast<const char*>(d.data() + at + 2),
                           strnlen(reinterpret_cast<const char*>(d.data() + at + 2), 16));
    const auto record_id = readLE<std::uint16_t>(d, at + 18);
    const auto length = readLE<std::uint16_t>(d, at + 20);
    const std::uint64_t p = at + 54;
    if (user == "laszip encoded" && record_id == 22204) {
      LaszipVlr& v = f.vlr;
      v.compressor = readLE<std::uint16_t>(d, p);
      v.coder = readLE<std::uint16_t>(d, p + 2);
      v.version_major = readLE<std::uint8_t>(d, p + 4);
      v.version_minor = readLE<std::uint8_t>(d, p + 5);
      v.version_revision = readLE<std::uint16_t>(d, p + 6);
      v.options = readLE<std::uint32_t>(d, p + 8);
      v.chunk_size = readLE<std::uint32_t>(d, p + 12);
      v.special_evlr_count = readLE<std::int64_t>(d, p + 16);
      v.special_evlr_offset = readLE<std::int64_t>(d, p + 24);
      const auto items = readLE<std::uint16_t>(d, p + 32);
      for (std::uint16_t k = 0; k < items; ++k) {
        LazItem item;
        item.type = ItemType(readLE<std::uint16_t>(d, p + 34 + 6 * k));
        item.size = readLE<std::uint16_t>(d, p + 36 + 6 * k);
        item.version = readLE<std::uint16_t>(d, p + 38 + 6 * k);
        v.items.push_back(item);
      }
      found = true;
    }
    at = p + length;
  }
  EXPECT_TRUE(found) << path << " has no laszip VLR";

  // The chunk table: its offset is the first 8 bytes of the point data; the table holds a
  // version (0), the chunk count, then per chunk its point count (variable chunks only) and byte
  // count, each coded against the previous chunk's with a 32-bit integer codec of 2 contexts.
  auto table = readLE<std::int64_t>(d, f.point_data_offset);
  if (table == -1) table = readLE<std::int64_t>(d, d.size() - 8);
  const auto chunk_count = readLE<std::uint32_t>(d, std::uint64_t(table) + 4);
  const std::span<const std::byte> coded =
      std::as_bytes(std::span(d)).subspan(std::size_t(table) + 8);
  ArithmeticDecoder dec;
  dec.start(coded);
  IntegerDecoder ic({.bits = 32, .contexts = 2});
  const bool variable = f.vlr.chunk_size == kVariableChunkSize;
  std::uint64_t offset = f.point_data_offset + 8;
  std::uint64_t points_left = f.point_count;
  std::int32_t last_points = 0, last_bytes = 0;
  for (std::uint32_t i = 0; i < chunk_count; ++i) {
    LazTestChunk c;
    if (variable) {
      last_points = ic.decode(dec, last_points, 0);
      c.points = std::uint32_t(last_points);
    } else {
      c.points = std::min<std::uint64_t>(f.vlr.chunk_size, points_left);
    }
    last_bytes = ic.decode(dec, last_bytes, 1);
    c.bytes = std::uint32_t(last_bytes);
    c.offset = offset;
    offset += c.bytes;
    points_left -= c.points;
    f.chunks.push_back(c);
  }
  EXPECT_TRUE(dec.ok()) << path << ": the chunk table does not decode";
  EXPECT_EQ(points_left, 0u) << path << ": the chunks do not hold the header's point count";
  EXPECT_LE(offset, std::uint64_t(table)) << path << ": the chunks overlap the chunk table";
  return f;
}

// FNV-1a, 64 bits: the checksum the expected values of the tests are stated in.
inline std::uint64_t fnv1a64(std::span<const std::byte> bytes,
                             std::uint64_t hash = 0xcbf29ce484222325ull) {
  for (std::byte b : bytes) {
    hash ^= std::uint64_t(b);
    hash *= 0x100000001b3ull;
  }
  return hash;
}

}  // namespace parallax::laz::testing
