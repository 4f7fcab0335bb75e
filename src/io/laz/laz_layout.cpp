#include "io/laz/laz_layout.h"

#include <cstring>

#include "core/byte_order.h"
#include "io/laz/arithmetic_decoder.h"
#include "io/laz/arithmetic_encoder.h"
#include "io/laz/integer_codec.h"

namespace parallax::laz {

const char* itemName(ItemType type) {
  switch (type) {
    case ItemType::Byte:
      return "BYTE";
    case ItemType::Short:
      return "SHORT";
    case ItemType::Integer:
      return "INTEGER";
    case ItemType::Long:
      return "LONG";
    case ItemType::Float:
      return "FLOAT";
    case ItemType::Double:
      return "DOUBLE";
    case ItemType::Point10:
      return "POINT10";
    case ItemType::GpsTime11:
      return "GPSTIME11";
    case ItemType::Rgb12:
      return "RGB12";
    case ItemType::Wavepacket13:
      return "WAVEPACKET13";
    case ItemType::Point14:
      return "POINT14";
    case ItemType::Rgb14:
      return "RGB14";
    case ItemType::RgbNir14:
      return "RGBNIR14";
    case ItemType::Wavepacket14:
      return "WAVEPACKET14";
    case ItemType::Byte14:
      return "BYTE14";
  }
  return "an unknown item";
}

namespace {

// The chunk table's integer coder: 32 bits, context 0 for point counts, 1 for byte sizes.
const IntegerCodecShape kTableShape{.bits = 32, .contexts = 2};

}  // namespace

LaszipVlr parseLaszipVlr(std::span<const std::byte> payload) {
  const std::size_t size = payload.size();
  if (size < kLaszipVlrFixedSize + 6 || (size - kLaszipVlrFixedSize) % 6 != 0) {
    throw UnsupportedItems("the laszip VLR has " + std::to_string(size) +
                           " bytes; expected 34 + 6 per item");
  }
  const std::byte* p = payload.data();
  LaszipVlr vlr;
  vlr.compressor = loadLE<std::uint16_t>(p);
  vlr.coder = loadLE<std::uint16_t>(p + 2);
  vlr.version_major = loadLE<std::uint8_t>(p + 4);
  vlr.version_minor = loadLE<std::uint8_t>(p + 5);
  vlr.version_revision = loadLE<std::uint16_t>(p + 6);
  vlr.options = loadLE<std::uint32_t>(p + 8);
  vlr.chunk_size = loadLE<std::uint32_t>(p + 12);
  vlr.special_evlr_count = loadLE<std::int64_t>(p + 16);
  vlr.special_evlr_offset = loadLE<std::int64_t>(p + 24);
  const std::size_t count = loadLE<std::uint16_t>(p + 32);
  if (count != (size - kLaszipVlrFixedSize) / 6) {
    throw UnsupportedItems("the laszip VLR lists " + std::to_string(count) + " items in room for " +
                           std::to_string((size - kLaszipVlrFixedSize) / 6));
  }
  for (std::size_t i = 0; i < count; ++i) {
    const std::byte* item = p + kLaszipVlrFixedSize + 6 * i;
    vlr.items.push_back({ItemType(loadLE<std::uint16_t>(item)), loadLE<std::uint16_t>(item + 2),
                         loadLE<std::uint16_t>(item + 4)});
  }
  return vlr;
}

std::vector<std::byte> laszipVlrPayload(const LaszipVlr& vlr) {
  std::vector<std::byte> out(kLaszipVlrFixedSize + 6 * vlr.items.size());
  std::byte* p = out.data();
  storeLE(p, vlr.compressor);
  storeLE(p + 2, vlr.coder);
  storeLE(p + 4, vlr.version_major);
  storeLE(p + 5, vlr.version_minor);
  storeLE(p + 6, vlr.version_revision);
  storeLE(p + 8, vlr.options);
  storeLE(p + 12, vlr.chunk_size);
  storeLE(p + 16, vlr.special_evlr_count);
  storeLE(p + 24, vlr.special_evlr_offset);
  storeLE(p + 32, std::uint16_t(vlr.items.size()));
  for (std::size_t i = 0; i < vlr.items.size(); ++i) {
    std::byte* item = p + kLaszipVlrFixedSize + 6 * i;
    storeLE(item, std::uint16_t(vlr.items[i].type));
    storeLE(item + 2, vlr.items[i].size);
    storeLE(item + 4, vlr.items[i].version);
  }
  return out;
}

std::vector<std::uint8_t> encodeChunkTable(std::span<const LazChunk> chunks, bool variable) {
  std::vector<std::uint8_t> out;
  if (chunks.empty()) return out;
  ArithmeticEncoder enc(out);
  IntegerEncoder ic(kTableShape);
  std::uint32_t last_points = 0, last_bytes = 0;
  for (const LazChunk& chunk : chunks) {
    if (variable) {
      ic.encode(enc, std::int32_t(last_points), std::int32_t(chunk.points), 0);
      last_points = std::uint32_t(chunk.points);
    }
    ic.encode(enc, std::int32_t(last_bytes), std::int32_t(chunk.bytes), 1);
    last_bytes = std::uint32_t(chunk.bytes);
  }
  enc.finish();
  return out;
}

bool decodeChunkTable(std::span<const std::byte> stream, std::uint32_t count, bool variable,
                      std::vector<std::uint32_t>& points, std::vector<std::uint32_t>& bytes) {
  points.clear();
  bytes.clear();
  if (count == 0) return true;
  ArithmeticDecoder dec;
  dec.start(stream);
  IntegerDecoder ic(kTableShape);
  std::uint32_t last_points = 0, last_bytes = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    if (variable) {
      last_points = std::uint32_t(ic.decode(dec, std::int32_t(last_points), 0));
      points.push_back(last_points);
    }
    last_bytes = std::uint32_t(ic.decode(dec, std::int32_t(last_bytes), 1));
    bytes.push_back(last_bytes);
    // Every entry costs some bits: a stream that ran out cannot hold the rest (this also bounds
    // the work a lying count can ask for).
    if (!dec.ok()) return false;
  }
  return true;
}

}  // namespace parallax::laz
