// The layered chunk (compressor 3; LAZ 1.4 specification, "layered chunks"; LASzip 3.x), as
// LASzip writes it:
//
//   first record, raw                      recordLength() bytes
//   point count of the chunk               uint32, the first point included
//   layer sizes                            uint32 each: POINT14's nine layers, then each other
//                                          item's layers in item order (RGB14 1, RGBNIR14 2,
//                                          WAVEPACKET14 1, BYTE14 one per byte)
//   layers                                 in the same order, back to back
//
// A layer whose values never changed over the chunk is empty (size 0), except POINT14's first
// two (channel/returns/XY and Z), which LASzip always writes. The decoder checks the header against
// the chunk's bytes and the count the reader expects before it decodes anything, and every layer
// stream against its own bytes afterwards.
#include <algorithm>
#include <cassert>
#include <cstring>
#include <limits>
#include <string>

#include "io/laz/layered_codec.h"
#include "io/laz/layered_items.h"
#include "io/laz/layered_point14.h"

namespace parallax::laz {

namespace {

using layered::ItemDecoder;
using layered::ItemEncoder;
using layered::kPoint14Layers;
using layered::kPoint14Size;
using layered::LayerFailure;
using layered::loadLE;

std::string describe(const LazItem& item, std::size_t index) {
  return "item " + std::to_string(index + 1) + " (" + itemName(item.type) + ", " +
         std::to_string(item.size) + " bytes, version " + std::to_string(item.version) + ")";
}

// Checks an item list for the layered codec; returns each item's codec version. LASzip reads
// version 2 of POINT14, RGB14, RGBNIR14 and BYTE14 as version 3 (files from its prototype); it
// writes only 3 and 4, and so does this encoder.
std::vector<unsigned> checkItems(std::span<const LazItem> items, bool encoding) {
  if (items.empty()) throw UnsupportedItems("the LASzip item list is empty");
  std::vector<unsigned> versions;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const LazItem& item = items[i];
    std::size_t expected_size = 0;
    switch (item.type) {
      case ItemType::Point14:
        expected_size = kPoint14Size;
        break;
      case ItemType::Rgb14:
        expected_size = 6;
        break;
      case ItemType::RgbNir14:
        expected_size = 8;
        break;
      case ItemType::Wavepacket14:
        expected_size = 29;
        break;
      case ItemType::Byte14:
        expected_size = item.size;
        break;
      default:
        throw UnsupportedItems(describe(item, i) +
                               ": not an item of layered chunks (point formats 6-10 hold POINT14, "
                               "RGB14, RGBNIR14, WAVEPACKET14 and BYTE14)");
    }
    if ((i == 0) != (item.type == ItemType::Point14)) {
      throw UnsupportedItems(describe(item, i) +
                             ": layered chunks hold one POINT14 item, the first");
    }
    if (item.size == 0) throw UnsupportedItems(describe(item, i) + ": expected at least 1 byte");
    if (item.size != expected_size) {
      throw UnsupportedItems(describe(item, i) + ": expected " + std::to_string(expected_size) +
                             " bytes");
    }
    const bool old_version = !encoding && item.version == 2 && item.type != ItemType::Wavepacket14;
    if (item.version != 3 && item.version != 4 && !old_version) {
      throw UnsupportedItems(describe(item, i) + ": " + (encoding ? "writes" : "reads") +
                             " versions 3 and 4 of layered items");
    }
    versions.push_back(old_version ? 3u : item.version);
  }
  return versions;
}

std::string layerName(ItemType type, std::size_t layer) {
  switch (type) {
    case ItemType::Point14:
      return layered::kPoint14LayerNames[layer];
    case ItemType::Rgb14:
      return "RGB";
    case ItemType::RgbNir14:
      return layer == 0 ? "RGB" : "NIR";
    case ItemType::Wavepacket14:
      return "wave packet";
    default:
      return "byte " + std::to_string(layer + 1);
  }
}

class LayeredDecoder final : public ChunkDecoder {
 public:
  LayeredDecoder(std::span<const LazItem> items, DecoderPath path)
      : items_(items.begin(), items.end()),
        point_(checkItems(items, false)[0]),
        general_(path == DecoderPath::kGeneral) {
    const std::vector<unsigned> versions = checkItems(items, false);
    record_length_ = kPoint14Size;
    layer_count_ = kPoint14Layers;
    // POINT14's layers after channel/returns/XY and Z, in layer order (layered_point14.h).
    layer_group_ = {0,
                    0,
                    fields::kClassification,
                    fields::kFlags,
                    fields::kIntensity,
                    fields::kScanAngle,
                    fields::kUserData,
                    fields::kPointSource,
                    fields::kGpsTime};
    for (std::size_t i = 1; i < items.size(); ++i) {
      const LazItem& item = items[i];
      std::unique_ptr<ItemDecoder> d;
      switch (item.type) {
        case ItemType::Rgb14:
          d = layered::makeRgbDecoder(false, versions[i]);
          layer_group_.push_back(fields::kRgb);
          break;
        case ItemType::RgbNir14:
          d = layered::makeRgbDecoder(true, versions[i]);
          layer_group_.push_back(fields::kRgb);
          layer_group_.push_back(fields::kNir);
          break;
        case ItemType::Wavepacket14:
          d = layered::makeWavepacketDecoder(versions[i]);
          layer_group_.push_back(fields::kWavePacket);
          break;
        default:
          d = layered::makeBytesDecoder(item.size, versions[i]);
          layer_group_.insert(layer_group_.end(), item.size, fields::kExtraBytes);
          break;
      }
      offsets_.push_back(record_length_);
      first_layer_.push_back(layer_count_);
      record_length_ += d->size();
      layer_count_ += d->layerCount();
      decoders_.push_back(std::move(d));
    }
    assert(layer_group_.size() == layer_count_ && "a group for every layer");
    layers_.resize(layer_count_);
  }

  std::size_t recordLength() const override { return record_length_; }

  void selectFields(std::uint32_t wanted) override { wanted_ = wanted; }

  void decode(std::span<const std::byte> chunk, std::size_t point_count,
              std::byte* records) override {
    if (point_count == 0) {
      if (!chunk.empty()) {
        throw ChunkCorrupt(0, "the chunk holds " + std::to_string(chunk.size()) +
                                  " bytes where no points were expected");
      }
      return;
    }
    readHeader(chunk, point_count);
    std::memcpy(records, chunk.data(), record_length_);
    if (decodePoints<false>(point_count, records) != kNoFailure) {
      // Something went wrong: decode again, checking every point, to name the first one.
      const std::size_t first_bad = decodePoints<true>(point_count, records);
      throw ChunkCorrupt(first_bad, failureMessage());
    }
  }

 private:
  // Reads the count and the layer sizes after the raw first record, checks them, and points
  // layers_ at the layers.
  void readHeader(std::span<const std::byte> chunk, std::size_t point_count) {
    if (chunk.size() < record_length_) {
      throw ChunkCorrupt(0, "the chunk's " + std::to_string(chunk.size()) +
                                " bytes cannot hold its first point (" +
                                std::to_string(record_length_) + " bytes)");
    }
    // The header governs every point after the first (in a chunk of one point, that one).
    const std::size_t first_coded = std::min<std::size_t>(1, point_count - 1);
    const std::size_t header = 4 + 4 * layer_count_;
    std::size_t pos = record_length_;
    if (chunk.size() - pos < header) {
      const std::string need = std::to_string(pos + header);
      throw ChunkCorrupt(first_coded, "the chunk ends inside its table of layer sizes (" +
                                          std::to_string(chunk.size()) + " bytes, " + need +
                                          " needed up to the first layer)");
    }
    const std::uint32_t count = loadLE<std::uint32_t>(chunk.data() + pos);
    if (count != point_count) {
      // Fewer points than expected: the missing ones are the first affected. More: the chunk
      // does not match its table, so no coded point can be trusted.
      const std::size_t first =
          count < point_count ? std::max<std::size_t>(count, first_coded) : first_coded;
      throw ChunkCorrupt(first, "the chunk says it holds " + std::to_string(count) +
                                    " points, the chunk table " + std::to_string(point_count));
    }
    pos += 4;
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < layer_count_; ++i) {
      total += loadLE<std::uint32_t>(chunk.data() + pos + 4 * i);
    }
    const std::size_t body = chunk.size() - pos - 4 * layer_count_;
    if (total != body) {
      throw ChunkCorrupt(first_coded, "the chunk's layers add up to " + std::to_string(total) +
                                          " bytes, but " + std::to_string(body) +
                                          " follow its table of layer sizes");
    }
    std::size_t at = pos + 4 * layer_count_;
    for (std::size_t i = 0; i < layer_count_; ++i) {
      const std::uint32_t size = loadLE<std::uint32_t>(chunk.data() + pos + 4 * i);
      layers_[i] = chunk.subspan(at, size);
      at += size;
      // A layer nobody asked for is handed over empty: its item then repeats the last value,
      // exactly as for a layer the writer left out, and not one of its bytes is read. Every
      // layer's context comes from the first two layers or from itself, so the layers decoded
      // are unchanged.
      if (layer_group_[i] != 0 && (wanted_ & layer_group_[i]) == 0) layers_[i] = {};
    }
  }

  void start(const std::byte* first) {
    const std::span<const std::span<const std::byte>> layers(layers_);
    const unsigned context = point_.start(first, layers.first(kPoint14Layers));
    for (std::size_t j = 0; j < decoders_.size(); ++j) {
      decoders_[j]->start(first + offsets_[j],
                          layers.subspan(first_layer_[j], decoders_[j]->layerCount()), context);
    }
  }

  bool failed() const {
    if (point_.failure()) return true;
    for (const auto& d : decoders_) {
      if (d->failure()) return true;
    }
    return false;
  }

  static constexpr std::size_t kNoFailure = std::numeric_limits<std::size_t>::max();

  // Decodes points 1..n-1 after the first. Returns kNoFailure, or where a layer was found
  // broken: with kCheckEach the first point after which it was (a layer too short to start
  // affects point 1, or in a one-point chunk point 0); without, a point some way after it (the
  // layers are checked every kCheckInterval points, so that a broken chunk claiming many points
  // stops early).
  template <bool kCheckEach>
  std::size_t decodePoints(std::size_t n, std::byte* records) {
    using layered::kCheckInterval;
    start(records);
    if (!kCheckEach && !general_) {
      // The fast path: POINT14 over the whole chunk (remembering each point's context), then
      // each other item over the whole chunk. An item none of whose layers is wanted is not
      // decoded at all (its bytes are unspecified, as selectFields says).
      contexts_.resize(n);
      std::byte* record = records;
      for (std::size_t i = 1; i < n; ++i) {
        record += record_length_;
        contexts_[i] = std::uint8_t(point_.decode(record));
        if (i % kCheckInterval == 0 && point_.failure()) return i;
      }
      for (std::size_t j = 0; j < decoders_.size(); ++j) {
        if (!wantedItem(j)) continue;
        const std::size_t done = decoders_[j]->decodeRun(records + record_length_ + offsets_[j],
                                                         n - 1, record_length_, &contexts_[1]);
        if (done != n - 1) return done;
      }
      return failed() ? n - 1 : kNoFailure;
    }
    if constexpr (kCheckEach) {
      if (failed()) return std::min<std::size_t>(1, n - 1);
    }
    std::byte* record = records;
    for (std::size_t i = 1; i < n; ++i) {
      record += record_length_;
      const unsigned context = point_.decode(record);
      for (std::size_t j = 0; j < decoders_.size(); ++j) {
        if (wantedItem(j)) decoders_[j]->decode(record + offsets_[j], context);
      }
      if (kCheckEach || i % kCheckInterval == 0) {
        if (failed()) return i;
      }
    }
    return failed() ? n - 1 : kNoFailure;
  }

  // Whether any layer of item j (after POINT14) was asked for.
  bool wantedItem(std::size_t j) const {
    for (std::size_t l = 0; l < decoders_[j]->layerCount(); ++l) {
      if (wanted_ & layer_group_[first_layer_[j] + l]) return true;
    }
    return false;
  }

  std::string failureMessage() const {
    LayerFailure f = point_.failure();
    std::size_t item = 0;
    for (std::size_t j = 0; !f && j < decoders_.size(); ++j) {
      f = decoders_[j]->failure();
      item = j + 1;
    }
    const std::size_t first = item == 0 ? 0 : first_layer_[item - 1];
    const std::size_t layer = first + std::size_t(f.layer);
    return "the " + layerName(items_[item].type, std::size_t(f.layer)) + " layer of " +
           itemName(items_[item].type) + " (" + std::to_string(layers_[layer].size()) + " bytes) " +
           (f.overran ? "runs past its end" : "holds an impossible value");
  }

  std::vector<LazItem> items_;
  layered::Point14Decoder point_;
  std::vector<std::unique_ptr<ItemDecoder>> decoders_;
  std::vector<std::size_t> offsets_;      // of each item after POINT14 in the record
  std::vector<std::size_t> first_layer_;  // of each item after POINT14
  std::size_t record_length_ = 0;
  std::size_t layer_count_ = 0;
  std::vector<std::span<const std::byte>> layers_;
  std::vector<std::uint32_t> layer_group_;  // the fields:: group of each layer; 0: always decoded
  std::uint32_t wanted_ = fields::kAll;
  std::vector<std::uint8_t> contexts_;  // each point's context, from POINT14 (fast path)
  bool general_ = false;  // point by point, every item through its virtual decode (tests)
};

class LayeredEncoder final : public ChunkEncoder {
 public:
  explicit LayeredEncoder(std::span<const LazItem> items) : point_(checkItems(items, true)[0]) {
    const std::vector<unsigned> versions = checkItems(items, true);
    record_length_ = kPoint14Size;
    for (std::size_t i = 1; i < items.size(); ++i) {
      const LazItem& item = items[i];
      std::unique_ptr<ItemEncoder> e;
      switch (item.type) {
        case ItemType::Rgb14:
          e = layered::makeRgbEncoder(false, versions[i]);
          break;
        case ItemType::RgbNir14:
          e = layered::makeRgbEncoder(true, versions[i]);
          break;
        case ItemType::Wavepacket14:
          e = layered::makeWavepacketEncoder(versions[i]);
          break;
        default:
          e = layered::makeBytesEncoder(item.size, versions[i]);
          break;
      }
      offsets_.push_back(record_length_);
      record_length_ += e->size();
      encoders_.push_back(std::move(e));
    }
  }

  std::size_t recordLength() const override { return record_length_; }

  void encode(const std::byte* records, std::size_t point_count,
              std::vector<std::uint8_t>& out) override {
    if (point_count == 0) return;
    assert(point_count <= 0xFFFFFFFFu && "a chunk counts its points in 32 bits");
    const auto* first = reinterpret_cast<const std::uint8_t*>(records);
    out.insert(out.end(), first, first + record_length_);

    unsigned context = point_.start(records);
    for (std::size_t j = 0; j < encoders_.size(); ++j) {
      encoders_[j]->start(records + offsets_[j], context);
    }
    const std::byte* record = records;
    for (std::size_t i = 1; i < point_count; ++i) {
      record += record_length_;
      context = point_.encode(record);
      for (std::size_t j = 0; j < encoders_.size(); ++j) {
        encoders_[j]->encode(record + offsets_[j], context);
      }
    }
    point_.finish();
    for (auto& e : encoders_) e->finish();

    const auto put32 = [&out](std::uint32_t v) {
      for (int b = 0; b < 4; ++b) out.push_back(std::uint8_t(v >> (8 * b)));
    };
    put32(std::uint32_t(point_count));
    const auto for_each_layer = [&](auto&& f) {
      for (std::size_t i = 0; i < kPoint14Layers; ++i) f(point_.layer(i));
      for (const auto& e : encoders_) {
        for (std::size_t i = 0; i < e->layerCount(); ++i) f(e->layer(i));
      }
    };
    for_each_layer([&](std::span<const std::uint8_t> l) { put32(std::uint32_t(l.size())); });
    for_each_layer(
        [&](std::span<const std::uint8_t> l) { out.insert(out.end(), l.begin(), l.end()); });
  }

 private:
  layered::Point14Encoder point_;
  std::vector<std::unique_ptr<ItemEncoder>> encoders_;
  std::vector<std::size_t> offsets_;
  std::size_t record_length_ = 0;
};

}  // namespace

std::unique_ptr<ChunkDecoder> makeLayeredDecoder(std::span<const LazItem> items, DecoderPath path) {
  return std::make_unique<LayeredDecoder>(items, path);
}

std::unique_ptr<ChunkEncoder> makeLayeredEncoder(std::span<const LazItem> items) {
  return std::make_unique<LayeredEncoder>(items);
}

}  // namespace parallax::laz
