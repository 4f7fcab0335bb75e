// WAVEPACKET14, versions 3 and 4: the 29 bytes of a waveform packet reference (descriptor index,
// 64-bit byte offset, packet size, return point location and the x, y, z(t) parametric line; LAS
// 1.4 R15, table 17) in one layer. The offset is usually the last offset, or the last offset plus
// the last packet's size; otherwise its difference is coded, or the offset in full.
#include <cassert>

#include "io/laz/integer_codec.h"
#include "io/laz/layered_items.h"

namespace parallax::laz::layered {

namespace {

inline constexpr std::size_t kWavepacketSize = 29;

struct Wavepacket {
  std::uint8_t index = 0;
  std::uint64_t offset = 0;
  std::uint32_t size = 0;
  std::int32_t return_point = 0;  // the floats' bits, coded as integers
  std::array<std::int32_t, 3> xyz{};

  static Wavepacket load(const std::byte* item) {
    Wavepacket w;
    w.index = std::uint8_t(item[0]);
    w.offset = loadLE<std::uint64_t>(item + 1);
    w.size = loadLE<std::uint32_t>(item + 9);
    w.return_point = loadLE<std::int32_t>(item + 13);
    for (int i = 0; i < 3; ++i) w.xyz[i] = loadLE<std::int32_t>(item + 17 + 4 * i);
    return w;
  }
  void store(std::byte* item) const {
    item[0] = std::byte(index);
    storeLE(item + 1, offset);
    storeLE(item + 9, size);
    storeLE(item + 13, return_point);
    for (int i = 0; i < 3; ++i) storeLE(item + 17 + 4 * i, xyz[i]);
  }
};

constexpr IntegerCodecShape kInt32{.bits = 32, .contexts = 1};

template <class IntegerCodec>
struct WavepacketModels {
  explicit WavepacketModels(bool for_decoding)
      : packet_index(256, for_decoding),
        offset_kind{{Lazy<SymbolModel>(4, for_decoding), Lazy<SymbolModel>(4, for_decoding),
                     Lazy<SymbolModel>(4, for_decoding), Lazy<SymbolModel>(4, for_decoding)}},
        offset_diff(kInt32),
        packet_size(kInt32),
        return_point(kInt32),
        xyz(IntegerCodecShape{.bits = 32, .contexts = 3}) {}
  void reset() {
    packet_index.reset();
    for (auto& m : offset_kind) m.reset();
    offset_diff.reset();
    packet_size.reset();
    return_point.reset();
    xyz.reset();
  }
  Lazy<SymbolModel> packet_index;
  // How the offset follows from the last one: 0 same, 1 + last size, 2 coded difference,
  // 3 in full; by the last point's kind.
  std::array<Lazy<SymbolModel>, 4> offset_kind;
  Lazy<IntegerCodec> offset_diff, packet_size, return_point, xyz;
  // Per context, besides the last packet.
  std::int32_t last_diff = 0;
  std::uint32_t last_kind = 0;
};

template <class IntegerCodec>
class WavepacketState {
 protected:
  WavepacketState(unsigned version, bool for_decoding)
      : version_(version), for_decoding_(for_decoding) {}
  void startChunk(const Wavepacket& first, unsigned context) {
    used_.fill(false);
    current_ = context;
    startContext(context, first);
  }
  void startContext(unsigned context, const Wavepacket& seed) {
    if (!models_[context]) {
      models_[context] = std::make_unique<WavepacketModels<IntegerCodec>>(for_decoding_);
    }
    models_[context]->reset();
    models_[context]->last_diff = 0;
    models_[context]->last_kind = 0;
    last_[context] = seed;
    used_[context] = true;
  }
  unsigned enter(unsigned context) {
    const ContextSwitch s = switchContext(current_, context, used_, version_);
    if (s.start_new) startContext(s.models, last_[current_]);
    current_ = s.models;
    return s.last;
  }

  unsigned version_;
  bool for_decoding_;
  std::array<std::unique_ptr<WavepacketModels<IntegerCodec>>, kChannels> models_;
  std::array<Wavepacket, kChannels> last_{};
  std::array<bool, kChannels> used_{};
  unsigned current_ = 0;
};

class WavepacketDecoder final : public ItemDecoder, WavepacketState<IntegerDecoder> {
 public:
  explicit WavepacketDecoder(unsigned version) : WavepacketState(version, true) {}
  std::size_t size() const override { return kWavepacketSize; }
  std::size_t layerCount() const override { return 1; }
  void start(const std::byte* first, std::span<const std::span<const std::byte>> layers,
             unsigned context) override {
    assert(layers.size() == 1 && "WAVEPACKET14 has one layer");
    present_ = !layers[0].empty();
    dec_.start(layers[0]);
    startChunk(Wavepacket::load(first), context);
  }
  LayerFailure failure() const override { return checkLayer(dec_, present_, 0); }

  std::size_t decodeRun(std::byte* item, std::size_t count, std::size_t stride,
                        const std::uint8_t* contexts) override {
    return decodeRunOf(*this, item, count, stride, contexts);
  }

  void decode(std::byte* item, unsigned context) override {
    Wavepacket& last = last_[enter(context)];
    if (present_) {
      WavepacketModels<IntegerDecoder>& m = *models_[current_];
      Wavepacket w;
      w.index = std::uint8_t(dec_.decodeSymbol(*m.packet_index));
      m.last_kind = dec_.decodeSymbol(*m.offset_kind[m.last_kind]);
      switch (m.last_kind) {
        case 0:
          w.offset = last.offset;
          break;
        case 1:
          w.offset = last.offset + last.size;
          break;
        case 2:
          m.last_diff = m.offset_diff->decode(dec_, m.last_diff);
          w.offset = last.offset + std::uint64_t(std::int64_t(m.last_diff));
          break;
        default:
          w.offset = dec_.readInt64();
          break;
      }
      w.size = std::uint32_t(m.packet_size->decode(dec_, std::int32_t(last.size)));
      w.return_point = m.return_point->decode(dec_, last.return_point);
      for (unsigned i = 0; i < 3; ++i) w.xyz[i] = m.xyz->decode(dec_, last.xyz[i], i);
      last = w;
    }
    last.store(item);
  }

 private:
  ArithmeticDecoder dec_;
  bool present_ = false;
};

class WavepacketEncoder final : public ItemEncoder, WavepacketState<IntegerEncoder> {
 public:
  explicit WavepacketEncoder(unsigned version) : WavepacketState(version, false) {}
  std::size_t size() const override { return kWavepacketSize; }
  std::size_t layerCount() const override { return 1; }
  void start(const std::byte* first, unsigned context) override {
    layer_.restart();
    changed_ = false;
    startChunk(Wavepacket::load(first), context);
  }
  void finish() override { layer_.finish(); }
  std::span<const std::uint8_t> layer(std::size_t) const override {
    return changed_ ? std::span<const std::uint8_t>(layer_.bytes) : std::span<const std::uint8_t>{};
  }

  void encode(const std::byte* item, unsigned context) override {
    Wavepacket& last = last_[enter(context)];
    WavepacketModels<IntegerEncoder>& m = *models_[current_];
    ArithmeticEncoder& enc = layer_.encoder;
    const Wavepacket w = Wavepacket::load(item);
    std::array<std::byte, kWavepacketSize> last_bytes;
    last.store(last_bytes.data());
    if (std::memcmp(item, last_bytes.data(), kWavepacketSize) != 0) changed_ = true;

    enc.encodeSymbol(*m.packet_index, w.index);
    const std::int64_t diff64 = std::int64_t(w.offset - last.offset);
    const std::int32_t diff32 = std::int32_t(diff64);
    std::uint32_t kind;
    if (diff64 != std::int64_t(diff32)) {
      kind = 3;
    } else if (diff32 == 0) {
      kind = 0;
    } else if (diff32 == std::int32_t(last.size)) {
      kind = 1;
    } else {
      kind = 2;
    }
    enc.encodeSymbol(*m.offset_kind[m.last_kind], kind);
    m.last_kind = kind;
    if (kind == 2) {
      m.offset_diff->encode(enc, m.last_diff, diff32);
      m.last_diff = diff32;
    } else if (kind == 3) {
      enc.writeInt64(w.offset);
    }
    m.packet_size->encode(enc, std::int32_t(last.size), std::int32_t(w.size));
    m.return_point->encode(enc, last.return_point, w.return_point);
    for (unsigned i = 0; i < 3; ++i) m.xyz->encode(enc, last.xyz[i], w.xyz[i], i);
    last = w;
  }

 private:
  LayerStream layer_;
  bool changed_ = false;
};

}  // namespace

std::unique_ptr<ItemDecoder> makeWavepacketDecoder(unsigned version) {
  return std::make_unique<WavepacketDecoder>(version);
}
std::unique_ptr<ItemEncoder> makeWavepacketEncoder(unsigned version) {
  return std::make_unique<WavepacketEncoder>(version);
}

}  // namespace parallax::laz::layered
