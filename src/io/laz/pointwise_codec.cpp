// The point-wise chunk codec: a chunk is its first record raw, then one arithmetic stream in
// which every following record's items are coded in record order (LAZ specification; Isenburg
// 2013). The items' coders (pointwise_*.cpp) keep their state from point to point; the chunk
// restarts them from the raw record.
#include "io/laz/pointwise_codec.h"

#include <string>
#include <type_traits>
#include <utility>

#include "io/laz/pointwise_gpstime.h"
#include "io/laz/pointwise_items.h"
#include "io/laz/pointwise_point10.h"
#include "io/laz/pointwise_rgb.h"

namespace parallax::laz {
namespace {

// Checks one item against what the point-wise codec defines; throws UnsupportedItems saying
// which item and why.
void checkItem(const LazItem& item, std::size_t index, std::size_t count) {
  const std::string where = "LAZ item " + std::to_string(index + 1) + " of " +
                            std::to_string(count) + " (" + itemName(item.type) + ", type " +
                            std::to_string(unsigned(item.type)) + ", " + std::to_string(item.size) +
                            " bytes, version " + std::to_string(item.version) + ")";
  std::size_t size = 0;
  int max_version = 2;
  switch (item.type) {
    case ItemType::Point10:
      size = 20;
      break;
    case ItemType::GpsTime11:
      size = 8;
      break;
    case ItemType::Rgb12:
      size = 6;
      break;
    case ItemType::Wavepacket13:
      size = 29;
      max_version = 1;
      break;
    case ItemType::Byte:
      if (item.size == 0) throw UnsupportedItems(where + ": a BYTE item needs at least one byte");
      size = item.size;
      break;
    case ItemType::Point14:
    case ItemType::Rgb14:
    case ItemType::RgbNir14:
    case ItemType::Wavepacket14:
    case ItemType::Byte14:
      throw UnsupportedItems(where +
                             ": a layered item (compressor 3) in a point-wise compressed file");
    default:
      throw UnsupportedItems(where + ": not an item LASzip's point-wise compressor defines");
  }
  if (item.size != size) {
    throw UnsupportedItems(where + ": expected " + std::to_string(size) + " bytes");
  }
  if (item.version < 1 || item.version > max_version) {
    throw UnsupportedItems(where + ": the point-wise codec defines versions 1" +
                           (max_version > 1 ? std::string(" and 2") : std::string(" only")));
  }
}

struct Empty {};

struct Layout {
  std::vector<std::size_t> offsets;
  std::size_t record_length = 0;
};

Layout checkItems(std::span<const LazItem> items) {
  if (items.empty()) throw UnsupportedItems("the LAZ item list is empty");
  Layout layout;
  for (std::size_t i = 0; i < items.size(); ++i) {
    checkItem(items[i], i, items.size());
    layout.offsets.push_back(layout.record_length);
    layout.record_length += items[i].size;
  }
  return layout;
}

// The general item set: any list of items, each decoded through its ItemDecoder (a virtual call
// per item and point).
class GeneralItems {
 public:
  GeneralItems(std::span<const LazItem> items, const Layout& layout) {
    for (std::size_t i = 0; i < items.size(); ++i) {
      const LazItem& item = items[i];
      std::unique_ptr<pointwise::ItemDecoder> coder;
      switch (item.type) {
        case ItemType::Point10:
          coder = pointwise::makePoint10Decoder(item.version);
          break;
        case ItemType::GpsTime11:
          coder = pointwise::makeGpsTimeDecoder(item.version);
          break;
        case ItemType::Rgb12:
          coder = pointwise::makeRgbDecoder(item.version);
          break;
        case ItemType::Wavepacket13:
          coder = pointwise::makeWavepacketDecoder();
          break;
        default:
          coder = pointwise::makeBytesDecoder(item.version, item.size);
          break;
      }
      slots_.push_back({std::move(coder), layout.offsets[i]});
    }
  }
  void start(const std::byte* first) {
    for (Slot& slot : slots_) slot.coder->start(first + slot.offset);
  }
  void decode(ArithmeticDecoder& dec, std::byte* out) {
    for (Slot& slot : slots_) slot.coder->decode(dec, out + slot.offset);
  }

 private:
  struct Slot {
    std::unique_ptr<pointwise::ItemDecoder> coder;
    std::size_t offset;
  };
  std::vector<Slot> slots_;
};

// The item sets nearly every point-wise LAZ file holds: POINT10, then GPSTIME11 and/or RGB12, all
// version 2 (point formats 0-3 as LASzip writes them). The items are members of known final
// types, so a point is one inlined sequence of their decoders: no virtual call and no loop over
// items per point. Decodes exactly what GeneralItems decodes (tests/io/test_laz_specialised.cpp).
template <bool kGpsTime, bool kRgb>
class Point10Items {
 public:
  static constexpr std::size_t kRgbOffset = kGpsTime ? 28 : 20;

  void start(const std::byte* first) {
    point_.start(first);
    if constexpr (kGpsTime) gps_.start(first + 20);
    if constexpr (kRgb) rgb_.start(first + kRgbOffset);
  }
  void decode(ArithmeticDecoder& dec, std::byte* out) {
    point_.decode(dec, out);
    if constexpr (kGpsTime) gps_.decode(dec, out + 20);
    if constexpr (kRgb) rgb_.decode(dec, out + kRgbOffset);
  }

  // Whether `items` is this set.
  static bool matches(std::span<const LazItem> items) {
    const std::size_t count = 1 + (kGpsTime ? 1 : 0) + (kRgb ? 1 : 0);
    if (items.size() != count) return false;
    std::size_t i = 0;
    const auto is = [&](ItemType type) { return items[i].type == type && items[i++].version == 2; };
    if (!is(ItemType::Point10)) return false;
    if (kGpsTime && !is(ItemType::GpsTime11)) return false;
    if (kRgb && !is(ItemType::Rgb12)) return false;
    return true;
  }

 private:
  pointwise::point10::Point10DecoderV2 point_;
  [[no_unique_address]] std::conditional_t<kGpsTime, pointwise::gpstime::GpsTimeDecoderV2, Empty>
      gps_;
  [[no_unique_address]] std::conditional_t<kRgb, pointwise::rgb::RgbDecoderV2, Empty> rgb_;
};

template <class Items>
class PointwiseDecoder final : public ChunkDecoder {
 public:
  template <class... Args>
  PointwiseDecoder(std::size_t record_length, Args&&... args)
      : items_(std::forward<Args>(args)...), record_length_(record_length) {}

  void decode(std::span<const std::byte> chunk, std::size_t point_count,
              std::byte* records) override {
    if (point_count == 0) return;
    const std::size_t used = decodePoints(chunk, point_count, records);
    // A valid stream ends exactly where the chunk does (the writer pads it for the decoder's
    // look-ahead); anything else means the chunk table and the data disagree.
    if (chunk.size() > record_length_ && used != chunk.size()) {
      throw ChunkCorrupt(0, "the compressed stream of " + std::to_string(point_count) +
                                " points ends after " + std::to_string(used) + " of the chunk's " +
                                std::to_string(chunk.size()) + " bytes");
    }
  }

  std::size_t decodeUnsized(std::span<const std::byte> bytes, std::size_t point_count,
                            std::byte* records) override {
    if (point_count == 0) return 0;
    return decodePoints(bytes, point_count, records);
  }

  std::size_t recordLength() const override { return record_length_; }

 private:
  // Decodes the records and returns the bytes of `chunk` they took.
  std::size_t decodePoints(std::span<const std::byte> chunk, std::size_t point_count,
                           std::byte* records) {
    const std::size_t length = record_length_;
    if (chunk.size() < length) {
      throw ChunkCorrupt(0, "the chunk has " + std::to_string(chunk.size()) +
                                " bytes, fewer than its first point's raw record of " +
                                std::to_string(length));
    }
    std::memcpy(records, chunk.data(), length);
    items_.start(records);
    const std::span<const std::byte> stream = chunk.subspan(length);
    dec_.start(stream);
    std::byte* out = records + length;
    for (std::size_t i = 1; i < point_count; ++i, out += length) {
      items_.decode(dec_, out);
      if (!dec_.ok()) {
        throw ChunkCorrupt(i, dec_.overran() ? "the compressed stream runs past the chunk's " +
                                                   std::to_string(chunk.size()) + " bytes"
                                             : "the compressed stream holds an impossible value");
      }
    }
    return length + dec_.consumed(stream);
  }

  Items items_;
  std::size_t record_length_ = 0;
  ArithmeticDecoder dec_;
};

// The specialised decoder for `items` when there is one.
template <bool kGpsTime, bool kRgb>
std::unique_ptr<ChunkDecoder> specialisedFor(std::span<const LazItem> items,
                                             std::size_t record_length) {
  if (!Point10Items<kGpsTime, kRgb>::matches(items)) return nullptr;
  return std::make_unique<PointwiseDecoder<Point10Items<kGpsTime, kRgb>>>(record_length);
}

class PointwiseEncoder final : public ChunkEncoder {
 public:
  explicit PointwiseEncoder(std::span<const LazItem> items) {
    Layout layout = checkItems(items);
    record_length_ = layout.record_length;
    for (std::size_t i = 0; i < items.size(); ++i) {
      const LazItem& item = items[i];
      std::unique_ptr<pointwise::ItemEncoder> coder;
      switch (item.type) {
        case ItemType::Point10:
          coder = pointwise::makePoint10Encoder(item.version);
          break;
        case ItemType::GpsTime11:
          coder = pointwise::makeGpsTimeEncoder(item.version);
          break;
        case ItemType::Rgb12:
          coder = pointwise::makeRgbEncoder(item.version);
          break;
        case ItemType::Wavepacket13:
          coder = pointwise::makeWavepacketEncoder();
          break;
        default:
          coder = pointwise::makeBytesEncoder(item.version, item.size);
          break;
      }
      items_.push_back({std::move(coder), layout.offsets[i]});
    }
  }

  void encode(const std::byte* records, std::size_t point_count,
              std::vector<std::uint8_t>& out) override {
    if (point_count == 0) return;
    const std::size_t length = record_length_;
    const auto* first = reinterpret_cast<const std::uint8_t*>(records);
    out.insert(out.end(), first, first + length);
    for (Slot& slot : items_) slot.coder->start(records + slot.offset);
    ArithmeticEncoder enc(out);
    const std::byte* in = records + length;
    for (std::size_t i = 1; i < point_count; ++i, in += length) {
      for (Slot& slot : items_) slot.coder->encode(enc, in + slot.offset);
    }
    enc.finish();
  }

  std::size_t recordLength() const override { return record_length_; }

 private:
  struct Slot {
    std::unique_ptr<pointwise::ItemEncoder> coder;
    std::size_t offset;
  };
  std::vector<Slot> items_;
  std::size_t record_length_ = 0;
};

}  // namespace

std::unique_ptr<ChunkDecoder> makePointwiseDecoder(std::span<const LazItem> items,
                                                   DecoderPath path) {
  const Layout layout = checkItems(items);
  if (path == DecoderPath::kSpecialised) {
    std::unique_ptr<ChunkDecoder> d = specialisedFor<true, true>(items, layout.record_length);
    if (!d) d = specialisedFor<true, false>(items, layout.record_length);
    if (!d) d = specialisedFor<false, true>(items, layout.record_length);
    if (!d) d = specialisedFor<false, false>(items, layout.record_length);
    if (d) return d;
  }
  return std::make_unique<PointwiseDecoder<GeneralItems>>(layout.record_length, items, layout);
}

std::unique_ptr<ChunkEncoder> makePointwiseEncoder(std::span<const LazItem> items) {
  return std::make_unique<PointwiseEncoder>(items);
}

}  // namespace parallax::laz
