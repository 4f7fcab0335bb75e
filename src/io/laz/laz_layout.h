// The file layer of LAZ: the "laszip encoded" VLR, the chunk table, and where each chunk's
// bytes and points are.
//
// Layout of the point data of a chunked LAZ file (compressors 2 and 3; LAZ 1.4 specification):
//   at the point data offset: int64, the byte offset of the chunk table (-1: the writer could
//     not seek back, and the offset is the file's last 8 bytes instead);
//   the chunks, back to back;
//   the chunk table: uint32 version (0), uint32 chunk count, then one arithmetic stream of the
//     chunks' point counts (variable chunk size only) and byte sizes, each predicted by the
//     previous chunk's through a 32-bit integer coder (contexts 0 and 1).
// Compressor 1 (point-wise, not chunked) has neither the offset nor a table: the point data is
// one chunk of every point.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/laz/chunk_codec.h"

namespace parallax::laz {

inline constexpr const char* kLaszipUserId = "laszip encoded";
inline constexpr std::uint16_t kLaszipRecordId = 22204;
inline constexpr std::size_t kLaszipVlrFixedSize = 34;  // before the 6-byte items

// Parses the VLR payload. Throws UnsupportedItems (the caller names the file) for a payload of
// the wrong size, or an item count that does not match it.
LaszipVlr parseLaszipVlr(std::span<const std::byte> payload);
// The payload of the VLR (34 bytes + 6 per item).
std::vector<std::byte> laszipVlrPayload(const LaszipVlr& vlr);

struct LazChunk {
  std::uint64_t offset = 0;       // of its first byte in the file
  std::uint64_t bytes = 0;        // its size
  std::uint64_t first_point = 0;  // index in the file of its first point
  std::uint64_t points = 0;
};

struct LazChunkTable {
  std::vector<LazChunk> chunks;
  bool recovered = false;  // no usable table: chunks to be found by decoding in order
  std::string note;        // why the table was not used (for messages)
};

// The chunk table's stream: point counts (when `variable`) and byte sizes.
std::vector<std::uint8_t> encodeChunkTable(std::span<const LazChunk> chunks, bool variable);

// Decodes `count` entries of a chunk table stream; false when the stream runs out (a truncated
// or corrupt table). `points` is filled only when `variable`.
bool decodeChunkTable(std::span<const std::byte> stream, std::uint32_t count, bool variable,
                      std::vector<std::uint32_t>& points, std::vector<std::uint32_t>& bytes);

}  // namespace parallax::laz
