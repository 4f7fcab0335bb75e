// BYTE (the extra bytes after the standard fields of formats 0-5) and WAVEPACKET13 (the 29-byte
// wave packet reference of formats 4 and 5).
//
// BYTE, version 2: each byte position is coded as its difference to the same byte of the last
// point (modulo 256), with a 256-symbol model per position. Version 1: the same difference
// through an 8-bit integer coder with a context per position.
//
// WAVEPACKET13 (version 1 only): the descriptor index as a symbol; the byte offset of the
// waveform as "the same", "right after the last packet", a 32-bit difference predicted by the
// last such difference, or 64 raw bits (a symbol chooses, in a context of the last choice); the
// packet size, return point location and x(t) y(t) z(t) (as their 32-bit patterns) predicted by
// their last values.
#include <cassert>
#include <vector>

#include "io/laz/integer_codec.h"
#include "io/laz/pointwise_items.h"

namespace parallax::laz::pointwise {
namespace {

class BytesDecoderV2 final : public ItemDecoder {
 public:
  explicit BytesDecoderV2(std::size_t count) : last_(count) {
    models_.reserve(count);
    for (std::size_t i = 0; i < count; ++i) models_.emplace_back(256, true);
  }
  void start(const std::byte* first) override {
    std::memcpy(last_.data(), first, last_.size());
    for (SymbolModel& m : models_) m.reset();
  }
  void decode(ArithmeticDecoder& dec, std::byte* out) override {
    for (std::size_t i = 0; i < last_.size(); ++i) {
      last_[i] = std::uint8_t(last_[i] + dec.decodeSymbol(models_[i]));
    }
    std::memcpy(out, last_.data(), last_.size());
  }

 private:
  std::vector<std::uint8_t> last_;
  std::vector<SymbolModel> models_;
};

class BytesEncoderV2 final : public ItemEncoder {
 public:
  explicit BytesEncoderV2(std::size_t count) : last_(count) {
    models_.reserve(count);
    for (std::size_t i = 0; i < count; ++i) models_.emplace_back(256, false);
  }
  void start(const std::byte* first) override {
    std::memcpy(last_.data(), first, last_.size());
    for (SymbolModel& m : models_) m.reset();
  }
  void encode(ArithmeticEncoder& enc, const std::byte* item) override {
    for (std::size_t i = 0; i < last_.size(); ++i) {
      const auto value = std::uint8_t(item[i]);
      enc.encodeSymbol(models_[i], std::uint8_t(value - last_[i]));
      last_[i] = value;
    }
  }

 private:
  std::vector<std::uint8_t> last_;
  std::vector<SymbolModel> models_;
};

IntegerCodecShape bytesV1Shape(std::size_t count) {
  return {.bits = 8, .contexts = std::uint32_t(count)};
}

class BytesDecoderV1 final : public ItemDecoder {
 public:
  explicit BytesDecoderV1(std::size_t count) : last_(count), ic_(bytesV1Shape(count)) {}
  void start(const std::byte* first) override {
    std::memcpy(last_.data(), first, last_.size());
    ic_.reset();
  }
  void decode(ArithmeticDecoder& dec, std::byte* out) override {
    for (std::size_t i = 0; i < last_.size(); ++i) {
      last_[i] = std::uint8_t(ic_.decode(dec, last_[i], std::uint32_t(i)));
    }
    std::memcpy(out, last_.data(), last_.size());
  }

 private:
  std::vector<std::uint8_t> last_;
  IntegerDecoder ic_;
};

class BytesEncoderV1 final : public ItemEncoder {
 public:
  explicit BytesEncoderV1(std::size_t count) : last_(count), ic_(bytesV1Shape(count)) {}
  void start(const std::byte* first) override {
    std::memcpy(last_.data(), first, last_.size());
    ic_.reset();
  }
  void encode(ArithmeticEncoder& enc, const std::byte* item) override {
    for (std::size_t i = 0; i < last_.size(); ++i) {
      const auto value = std::uint8_t(item[i]);
      ic_.encode(enc, last_[i], value, std::uint32_t(i));
      last_[i] = value;
    }
  }

 private:
  std::vector<std::uint8_t> last_;
  IntegerEncoder ic_;
};

// ---------------------------------------------------------------------------------------------

// The 28 bytes after the descriptor index (LAS 1.4 R15 Table 13).
struct WavePacket {
  std::uint64_t offset = 0;
  std::uint32_t size = 0;
  std::int32_t location = 0;  // return point location, x(t), y(t), z(t): float bit patterns
  std::int32_t x = 0, y = 0, z = 0;

  static WavePacket load(const std::byte* p) {
    return {loadLE<std::uint64_t>(p),     loadLE<std::uint32_t>(p + 8),
            loadLE<std::int32_t>(p + 12), loadLE<std::int32_t>(p + 16),
            loadLE<std::int32_t>(p + 20), loadLE<std::int32_t>(p + 24)};
  }
  void store(std::byte* p) const {
    storeLE(p, offset);
    storeLE(p + 8, size);
    storeLE(p + 12, location);
    storeLE(p + 16, x);
    storeLE(p + 20, y);
    storeLE(p + 24, z);
  }
};

const IntegerCodecShape kWave32{.bits = 32, .contexts = 1};
const IntegerCodecShape kWaveXyz{.bits = 32, .contexts = 3};

template <bool kDecoding>
struct WaveModels {
  SymbolModel index{256, kDecoding};
  std::array<SymbolModel, 4> offset_kind{SymbolModel(4, kDecoding), SymbolModel(4, kDecoding),
                                         SymbolModel(4, kDecoding), SymbolModel(4, kDecoding)};
  WavePacket last;
  std::int32_t last_offset_diff = 0;
  std::uint32_t last_kind = 0;

  void reset(const std::byte* first) {
    last = WavePacket::load(first + 1);
    last_offset_diff = 0;
    last_kind = 0;
    index.reset();
    for (SymbolModel& m : offset_kind) m.reset();
  }
};

class WavepacketDecoder final : public ItemDecoder {
 public:
  void start(const std::byte* first) override {
    m_.reset(first);
    for (IntegerDecoder* c : {&offset_diff_, &size_, &location_, &xyz_}) c->reset();
  }
  void decode(ArithmeticDecoder& dec, std::byte* out) override {
    out[0] = std::byte(dec.decodeSymbol(m_.index));
    const WavePacket& last = m_.last;
    WavePacket p;
    m_.last_kind = dec.decodeSymbol(m_.offset_kind[m_.last_kind]);
    switch (m_.last_kind) {
      case 0:
        p.offset = last.offset;
        break;
      case 1:
        p.offset = last.offset + last.size;
        break;
      case 2:
        m_.last_offset_diff = offset_diff_.decode(dec, m_.last_offset_diff);
        p.offset = last.offset + std::uint64_t(std::int64_t(m_.last_offset_diff));
        break;
      default:
        p.offset = dec.readInt64();
        break;
    }
    p.size = std::uint32_t(size_.decode(dec, std::int32_t(last.size)));
    p.location = location_.decode(dec, last.location);
    p.x = xyz_.decode(dec, last.x, 0);
    p.y = xyz_.decode(dec, last.y, 1);
    p.z = xyz_.decode(dec, last.z, 2);
    p.store(out + 1);
    m_.last = p;
  }

 private:
  WaveModels<true> m_;
  IntegerDecoder offset_diff_{kWave32}, size_{kWave32}, location_{kWave32}, xyz_{kWaveXyz};
};

class WavepacketEncoder final : public ItemEncoder {
 public:
  void start(const std::byte* first) override {
    m_.reset(first);
    for (IntegerEncoder* c : {&offset_diff_, &size_, &location_, &xyz_}) c->reset();
  }
  void encode(ArithmeticEncoder& enc, const std::byte* item) override {
    enc.encodeSymbol(m_.index, std::uint8_t(item[0]));
    const WavePacket p = WavePacket::load(item + 1);
    const WavePacket& last = m_.last;
    const std::int64_t diff64 = std::int64_t(p.offset - last.offset);
    const auto diff32 = std::int32_t(diff64);
    SymbolModel& kind = m_.offset_kind[m_.last_kind];
    if (diff64 == std::int64_t(diff32)) {
      if (diff32 == 0) {
        m_.last_kind = 0;
      } else if (diff32 == std::int32_t(last.size)) {
        m_.last_kind = 1;
      } else {
        m_.last_kind = 2;
      }
      enc.encodeSymbol(kind, m_.last_kind);
      if (m_.last_kind == 2) {
        offset_diff_.encode(enc, m_.last_offset_diff, diff32);
        m_.last_offset_diff = diff32;
      }
    } else {
      m_.last_kind = 3;
      enc.encodeSymbol(kind, 3);
      enc.writeInt64(p.offset);
    }
    size_.encode(enc, std::int32_t(last.size), std::int32_t(p.size));
    location_.encode(enc, last.location, p.location);
    xyz_.encode(enc, last.x, p.x, 0);
    xyz_.encode(enc, last.y, p.y, 1);
    xyz_.encode(enc, last.z, p.z, 2);
    m_.last = p;
  }

 private:
  WaveModels<false> m_;
  IntegerEncoder offset_diff_{kWave32}, size_{kWave32}, location_{kWave32}, xyz_{kWaveXyz};
};

}  // namespace

std::unique_ptr<ItemDecoder> makeBytesDecoder(int version, std::size_t count) {
  assert((version == 1 || version == 2) && count > 0 && "BYTE: versions 1 and 2, 1+ bytes");
  if (version == 1) return std::make_unique<BytesDecoderV1>(count);
  return std::make_unique<BytesDecoderV2>(count);
}

std::unique_ptr<ItemEncoder> makeBytesEncoder(int version, std::size_t count) {
  assert((version == 1 || version == 2) && count > 0 && "BYTE: versions 1 and 2, 1+ bytes");
  if (version == 1) return std::make_unique<BytesEncoderV1>(count);
  return std::make_unique<BytesEncoderV2>(count);
}

std::unique_ptr<ItemDecoder> makeWavepacketDecoder() {
  return std::make_unique<WavepacketDecoder>();
}

std::unique_ptr<ItemEncoder> makeWavepacketEncoder() {
  return std::make_unique<WavepacketEncoder>();
}

}  // namespace parallax::laz::pointwise
