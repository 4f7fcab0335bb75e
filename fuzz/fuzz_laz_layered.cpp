// libFuzzer target for the layered LAZ chunk decoder (compressor 3, point formats 6-10): any
// chunk bytes must decode or throw ChunkCorrupt, never crash, hang, read outside the chunk or
// allocate beyond what the item description justifies.
//
// Input: one byte choosing the items, then the chunk.
//   bits 0-2: point format 6 + (value % 5): 6 POINT14, 7 + RGB14, 8 + RGBNIR14, 9 + WAVEPACKET14,
//             10 + RGBNIR14 + WAVEPACKET14
//   bit 3:    item version 3 (0) or 4 (1)
//   bits 4-6: extra bytes (BYTE14) per record, 0-7
// The point count the reader would expect is the chunk's own (capped, so that the records fit in
// a few MB); the cap also exercises the decoder's count check. The seeds (fuzz/corpus/
// laz_layered/) are small chunks of every format written by Parallax's layered encoder (other
// writers' chunks reach this decoder through fuzz_laz_reader's and fuzz_copc_reader's real seeds).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <vector>

#include "io/laz/chunk_codec.h"
#include "io/laz/layered_codec.h"

namespace {

using parallax::laz::ChunkCorrupt;
using parallax::laz::ChunkDecoder;
using parallax::laz::ItemType;
using parallax::laz::LazItem;

constexpr std::uint32_t kMaxPoints = 1u << 14;

// One decoder per item choice, kept across inputs: a decoder must stay usable after a corrupt
// chunk, and this exercises that too.
ChunkDecoder& decoderFor(std::uint8_t choice) {
  static std::array<std::unique_ptr<ChunkDecoder>, 128> decoders;
  choice &= 0x7F;
  if (!decoders[choice]) {
    const int format = 6 + (choice & 7) % 5;
    const auto version = std::uint16_t((choice & 8) ? 4 : 3);
    const auto extra = std::uint16_t((choice >> 4) & 7);
    std::vector<LazItem> items{{ItemType::Point14, 30, version}};
    if (format == 7) items.push_back({ItemType::Rgb14, 6, version});
    if (format == 8 || format == 10) items.push_back({ItemType::RgbNir14, 8, version});
    if (format == 9 || format == 10) items.push_back({ItemType::Wavepacket14, 29, version});
    if (extra != 0) items.push_back({ItemType::Byte14, extra, version});
    decoders[choice] = parallax::laz::makeLayeredDecoder(items);
  }
  return *decoders[choice];
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  ChunkDecoder& decoder = decoderFor(data[0]);
  const std::span<const std::byte> chunk(reinterpret_cast<const std::byte*>(data + 1), size - 1);
  const std::size_t length = decoder.recordLength();
  std::uint32_t points = chunk.empty() ? 0 : 1;
  if (chunk.size() >= length + 4) {
    std::memcpy(&points, chunk.data() + length, 4);
    if (points > kMaxPoints) points = kMaxPoints;
  }
  std::vector<std::byte> records(std::size_t(points) * length);
  try {
    decoder.decode(chunk, points, records.data());
  } catch (const ChunkCorrupt& e) {
    // The first point affected must lie in the chunk (point 0 when no points were expected).
    if (e.point() >= std::max<std::uint32_t>(points, 1)) __builtin_trap();
  }
  return 0;
}
