// What every LAZ chunk codec implements, and the description of a LAZ file's point items.
//
// A LAZ file stores its point records in chunks (LAZ 1.4 specification; Isenburg 2013). Each
// chunk restarts every model, so chunks decode independently (and in parallel). Two chunk
// layouts exist:
//   - compressor 2, "point-wise" (point formats 0-5): the first point raw, then one arithmetic
//     stream in which each point's items follow each other (items POINT10, GPSTIME11, RGB12,
//     WAVEPACKET13, BYTE; versions 1 and 2);
//   - compressor 3, "layered" (point formats 6-10): the first point raw, the chunk's point
//     count, the byte size of every layer, then the layers, one arithmetic stream per field
//     group, so a reader can skip the fields it does not need (items POINT14, RGB14, RGBNIR14,
//     WAVEPACKET14, BYTE14; versions 3 and 4).
// A codec turns a chunk into raw LAS point records and back: the records are exactly the bytes
// an uncompressed LAS file of the same points holds, so the LAS record decoder makes columns of
// them, and a LAZ file can be checked record by record against its LAS twin.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace parallax::laz {

// Item types of the LASzip VLR (the record's fields, in record order).
enum class ItemType : std::uint16_t {
  Byte = 0,  // "extra bytes" of formats 0-5, `size` of them
  Short = 1,
  Integer = 2,
  Long = 3,
  Float = 4,
  Double = 5,
  Point10 = 6,        // the 20 bytes of formats 0-5
  GpsTime11 = 7,      // 8 bytes
  Rgb12 = 8,          // 6 bytes
  Wavepacket13 = 9,   // 29 bytes
  Point14 = 10,       // the 30 bytes of formats 6-10 (GPS time included)
  Rgb14 = 11,         // 6 bytes
  RgbNir14 = 12,      // 8 bytes
  Wavepacket14 = 13,  // 29 bytes
  Byte14 = 14,        // extra bytes of formats 6-10
};

// The item's name as LASzip writes it ("POINT10", "BYTE14"), for messages; "an unknown item"
// for a type the format does not define.
const char* itemName(ItemType type);

struct LazItem {
  ItemType type = ItemType::Byte;
  std::uint16_t size = 0;     // bytes of this item in each record
  std::uint16_t version = 0;  // the codec version of the item (1, 2, 3 or 4)
};

// The "laszip encoded" VLR (user id "laszip encoded", record id 22204).
struct LaszipVlr {
  std::uint16_t compressor = 0;  // 0 none, 1 point-wise, 2 point-wise chunked, 3 layered chunked
  std::uint16_t coder = 0;       // 0: arithmetic (the only one defined)
  std::uint8_t version_major = 0, version_minor = 0;
  std::uint16_t version_revision = 0;
  std::uint32_t options = 0;
  std::uint32_t chunk_size = 0;  // points per chunk; kVariableChunkSize: per the chunk table
  std::int64_t special_evlr_count = -1;
  std::int64_t special_evlr_offset = -1;
  std::vector<LazItem> items;

  // Sum of the item sizes: the record length the items describe.
  std::size_t recordLength() const {
    std::size_t n = 0;
    for (const LazItem& item : items) n += item.size;
    return n;
  }
};

inline constexpr std::uint32_t kVariableChunkSize = 0xFFFFFFFFu;

// Thrown by a codec for a chunk it cannot decode: the index of the first point affected inside
// the chunk, and why. The reader turns it into an InputError naming the file, the chunk and its
// byte offset.
class ChunkCorrupt : public std::runtime_error {
 public:
  ChunkCorrupt(std::size_t point, const std::string& what)
      : std::runtime_error(what), point_(point) {}
  std::size_t point() const { return point_; }

 private:
  std::size_t point_;
};

// Thrown by the codec factories for an item list they cannot code (an unknown item type or
// version, a size that does not match the type): says which item and why.
class UnsupportedItems : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The groups of fields a reader may leave undecoded (a bit mask). In a layered chunk each group is
// one or more layers of its own, preceded by its byte count, so a group nobody asked for is skipped
// without decoding a symbol of it (the LAZ 1.4 design: a viewer reads x, y, z and colour only).
// Positions, return numbers and scanner channels (POINT14's first two layers, which carry what
// every other layer's context needs) are always decoded. Point-wise chunks (formats 0-5) are one
// stream in which every field depends on the previous ones: they always decode everything.
namespace fields {
inline constexpr std::uint32_t kClassification = 1u << 0;  // the classification byte
inline constexpr std::uint32_t kFlags = 1u << 1;      // classification flags, scan direction, edge
inline constexpr std::uint32_t kIntensity = 1u << 2;  // 16 bits
inline constexpr std::uint32_t kScanAngle = 1u << 3;
inline constexpr std::uint32_t kUserData = 1u << 4;
inline constexpr std::uint32_t kPointSource = 1u << 5;
inline constexpr std::uint32_t kGpsTime = 1u << 6;
inline constexpr std::uint32_t kRgb = 1u << 7;
inline constexpr std::uint32_t kNir = 1u << 8;
inline constexpr std::uint32_t kWavePacket = 1u << 9;
inline constexpr std::uint32_t kExtraBytes = 1u << 10;
inline constexpr std::uint32_t kAll = (1u << 11) - 1;
inline constexpr std::uint32_t kPositionsOnly = 0;
}  // namespace fields

// Which chunk loop a decoder factory builds: the one specialised for the item set when there is
// one (the common sets: formats 0-3 point-wise, each item through its concrete type; layered
// chunks one item at a time over the whole chunk), or the general one every item set can go
// through (a virtual call per item and point). Both decode the same records; the tests and the
// benchmark compare them.
enum class DecoderPath { kSpecialised, kGeneral };

// Decodes whole chunks into raw records. One object per thread; it keeps its models between
// chunks and resets them at the start of each.
class ChunkDecoder {
 public:
  virtual ~ChunkDecoder() = default;
  // Decode only the groups of `wanted` (fields::k*; every group by default) from the next chunk
  // on. In the records decode() writes, the bytes of a group not decoded are unspecified (they
  // repeat an earlier point's); the bytes of the groups decoded are exactly a full decode's.
  // Codecs that cannot skip (point-wise) decode everything whatever is asked.
  virtual void selectFields(std::uint32_t wanted) { (void)wanted; }
  // Decodes `point_count` records (each recordLength() bytes) from `chunk`, the chunk's bytes
  // as the chunk table delimits them, into `records`. Throws ChunkCorrupt when the stream runs
  // past the chunk's bytes, holds an impossible value, or (layered) disagrees with its own
  // point count and layer sizes.
  virtual void decode(std::span<const std::byte> chunk, std::size_t point_count,
                      std::byte* records) = 0;
  // For a file without a usable chunk table: decodes a chunk of `point_count` records whose end
  // is not known (`bytes` runs from its start to the end of the point data, or a window of it)
  // and returns the bytes it took, where the next chunk starts. Codecs that cannot delimit a
  // chunk this way throw ChunkCorrupt (the default).
  virtual std::size_t decodeUnsized(std::span<const std::byte> bytes, std::size_t point_count,
                                    std::byte* records) {
    (void)bytes, (void)point_count, (void)records;
    throw ChunkCorrupt(0, "this codec cannot find a chunk's end without the chunk table");
  }
  virtual std::size_t recordLength() const = 0;
};

// Encodes raw records into chunks. One object per thread, reused between chunks.
class ChunkEncoder {
 public:
  virtual ~ChunkEncoder() = default;
  // Appends the chunk that holds `point_count` records (each recordLength() bytes) to `out`.
  virtual void encode(const std::byte* records, std::size_t point_count,
                      std::vector<std::uint8_t>& out) = 0;
  virtual std::size_t recordLength() const = 0;
};

}  // namespace parallax::laz
