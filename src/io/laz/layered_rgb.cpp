// RGB14 and RGBNIR14, versions 3 and 4: red, green and blue (16 bits each) in one layer, and for
// RGBNIR14 near infrared in a second. Each 16-bit colour is coded as two bytes; a symbol says
// which bytes changed (and whether green and blue differ from red), then each changed byte is
// coded as a difference from the last value, green and blue predicted from red's change
// (Isenburg 2013, "RGB"; the layered variant keeps one set of models per scanner channel).
#include <cassert>

#include "io/laz/layered_items.h"

namespace parallax::laz::layered {

namespace {

std::uint32_t clampByte(std::int32_t v) {
  return v <= 0 ? 0u : v >= 255 ? 255u : std::uint32_t(v);
}

struct RgbModels {
  explicit RgbModels(bool for_decoding)
      : rgb_used(128, for_decoding),
        rgb_diff{{Lazy<SymbolModel>(256, for_decoding), Lazy<SymbolModel>(256, for_decoding),
                  Lazy<SymbolModel>(256, for_decoding), Lazy<SymbolModel>(256, for_decoding),
                  Lazy<SymbolModel>(256, for_decoding), Lazy<SymbolModel>(256, for_decoding)}},
        nir_used(4, for_decoding),
        nir_diff{{Lazy<SymbolModel>(256, for_decoding), Lazy<SymbolModel>(256, for_decoding)}} {}
  void reset() {
    rgb_used.reset();
    for (auto& m : rgb_diff) m.reset();
    nir_used.reset();
    for (auto& m : nir_diff) m.reset();
  }
  Lazy<SymbolModel> rgb_used;  // bit i: byte i changed (low/high of R, G, B); bit 6: G or B != R
  std::array<Lazy<SymbolModel>, 6> rgb_diff;
  Lazy<SymbolModel> nir_used;
  std::array<Lazy<SymbolModel>, 2> nir_diff;
};

// 16-bit colour channels: R, G, B and, with NIR, N.
using Colour = std::array<std::uint16_t, 4>;

Colour loadColour(const std::byte* item, bool nir) {
  Colour c{};
  for (int i = 0; i < (nir ? 4 : 3); ++i) c[i] = loadLE<std::uint16_t>(item + 2 * i);
  return c;
}
void storeColour(std::byte* item, const Colour& c, bool nir) {
  for (int i = 0; i < (nir ? 4 : 3); ++i) storeLE(item + 2 * i, c[i]);
}

// The part both directions share: four channel contexts, each with its models and last colour.
class RgbState {
 protected:
  RgbState(bool nir, unsigned version, bool for_decoding)
      : nir_(nir), version_(version), for_decoding_(for_decoding) {}

  void startChunk(const Colour& first, unsigned context) {
    used_.fill(false);
    current_ = context;
    startContext(context, first);
  }
  void startContext(unsigned context, const Colour& seed) {
    if (!models_[context]) models_[context] = std::make_unique<RgbModels>(for_decoding_);
    models_[context]->reset();
    last_[context] = seed;
    used_[context] = true;
  }
  // Switches to the point's context; returns the context whose last colour predicts it.
  unsigned enter(unsigned context) {
    const ContextSwitch s = switchContext(current_, context, used_, version_);
    if (s.start_new) startContext(s.models, last_[current_]);
    current_ = s.models;
    return s.last;
  }

  bool nir_;
  unsigned version_;
  bool for_decoding_;
  std::array<std::unique_ptr<RgbModels>, kChannels> models_;
  std::array<Colour, kChannels> last_{};
  std::array<bool, kChannels> used_{};
  unsigned current_ = 0;
};

class RgbDecoder final : public ItemDecoder, RgbState {
 public:
  RgbDecoder(bool nir, unsigned version) : RgbState(nir, version, true) {}
  std::size_t size() const override { return nir_ ? 8 : 6; }
  std::size_t layerCount() const override { return nir_ ? 2 : 1; }

  void start(const std::byte* first, std::span<const std::span<const std::byte>> layers,
             unsigned context) override {
    assert(layers.size() == layerCount() && "one layer per colour group");
    rgb_present_ = !layers[0].empty();
    rgb_.start(layers[0]);
    nir_present_ = nir_ && !layers[1].empty();
    if (nir_) nir_dec_.start(layers[1]);
    startChunk(loadColour(first, nir_), context);
  }

  LayerFailure failure() const override {
    if (LayerFailure f = checkLayer(rgb_, rgb_present_, 0)) return f;
    return checkLayer(nir_dec_, nir_present_, 1);
  }

  std::size_t decodeRun(std::byte* item, std::size_t count, std::size_t stride,
                        const std::uint8_t* contexts) override {
    return decodeRunOf(*this, item, count, stride, contexts);
  }

  void decode(std::byte* item, unsigned context) override {
    Colour& last = last_[enter(context)];
    RgbModels& m = *models_[current_];
    Colour c = last;
    if (rgb_present_) {
      const std::uint32_t used = rgb_.decodeSymbol(*m.rgb_used);
      // Red: each byte as a difference from the last red (mod 256).
      std::uint32_t lo = last[0] & 0xFF, hi = last[0] >> 8;
      if (used & 1) lo = (lo + rgb_.decodeSymbol(*m.rgb_diff[0])) & 0xFF;
      if (used & 2) hi = (hi + rgb_.decodeSymbol(*m.rgb_diff[1])) & 0xFF;
      c[0] = std::uint16_t(lo | hi << 8);
      if (used & (1u << 6)) {
        // Green and blue: predicted by the last value plus red's change (blue: the average of
        // red's and green's change), each byte separately.
        std::int32_t d = std::int32_t(c[0] & 0xFF) - std::int32_t(last[0] & 0xFF);
        std::uint32_t g_lo = last[1] & 0xFF, b_lo = last[2] & 0xFF;
        if (used & (1u << 2)) {
          g_lo = (rgb_.decodeSymbol(*m.rgb_diff[2]) + clampByte(d + std::int32_t(last[1] & 0xFF))) &
                 0xFF;
        }
        if (used & (1u << 4)) {
          d = (d + std::int32_t(g_lo) - std::int32_t(last[1] & 0xFF)) / 2;
          b_lo = (rgb_.decodeSymbol(*m.rgb_diff[4]) + clampByte(d + std::int32_t(last[2] & 0xFF))) &
                 0xFF;
        }
        d = std::int32_t(c[0] >> 8) - std::int32_t(last[0] >> 8);
        std::uint32_t g_hi = last[1] >> 8, b_hi = last[2] >> 8;
        if (used & (1u << 3)) {
          g_hi = (rgb_.decodeSymbol(*m.rgb_diff[3]) + clampByte(d + std::int32_t(last[1] >> 8))) &
                 0xFF;
        }
        if (used & (1u << 5)) {
          d = (d + std::int32_t(g_hi) - std::int32_t(last[1] >> 8)) / 2;
          b_hi = (rgb_.decodeSymbol(*m.rgb_diff[5]) + clampByte(d + std::int32_t(last[2] >> 8))) &
                 0xFF;
        }
        c[1] = std::uint16_t(g_lo | g_hi << 8);
        c[2] = std::uint16_t(b_lo | b_hi << 8);
      } else {
        c[1] = c[2] = c[0];  // grey
      }
      last[0] = c[0];
      last[1] = c[1];
      last[2] = c[2];
    }
    if (nir_present_) {
      const std::uint32_t used = nir_dec_.decodeSymbol(*m.nir_used);
      std::uint32_t lo = last[3] & 0xFF, hi = last[3] >> 8;
      if (used & 1) lo = (lo + nir_dec_.decodeSymbol(*m.nir_diff[0])) & 0xFF;
      if (used & 2) hi = (hi + nir_dec_.decodeSymbol(*m.nir_diff[1])) & 0xFF;
      c[3] = last[3] = std::uint16_t(lo | hi << 8);
    }
    storeColour(item, c, nir_);
  }

 private:
  ArithmeticDecoder rgb_, nir_dec_;
  bool rgb_present_ = false, nir_present_ = false;
};

class RgbEncoder final : public ItemEncoder, RgbState {
 public:
  RgbEncoder(bool nir, unsigned version) : RgbState(nir, version, false) {}
  std::size_t size() const override { return nir_ ? 8 : 6; }
  std::size_t layerCount() const override { return nir_ ? 2 : 1; }

  void start(const std::byte* first, unsigned context) override {
    rgb_.restart();
    nir_layer_.restart();
    rgb_changed_ = nir_changed_ = false;
    startChunk(loadColour(first, nir_), context);
  }
  void finish() override {
    rgb_.finish();
    if (nir_) nir_layer_.finish();
  }
  std::span<const std::uint8_t> layer(std::size_t i) const override {
    if (i == 0)
      return rgb_changed_ ? std::span<const std::uint8_t>(rgb_.bytes)
                          : std::span<const std::uint8_t>{};
    return nir_changed_ ? std::span<const std::uint8_t>(nir_layer_.bytes)
                        : std::span<const std::uint8_t>{};
  }

  void encode(const std::byte* item, unsigned context) override {
    Colour& last = last_[enter(context)];
    RgbModels& m = *models_[current_];
    const Colour c = loadColour(item, nir_);
    ArithmeticEncoder& enc = rgb_.encoder;
    const auto lo = [](std::uint16_t v) { return std::int32_t(v & 0xFF); };
    const auto hi = [](std::uint16_t v) { return std::int32_t(v >> 8); };
    std::uint32_t used = 0;
    for (int i = 0; i < 3; ++i) {
      if (lo(c[i]) != lo(last[i])) used |= 1u << (2 * i);
      if (hi(c[i]) != hi(last[i])) used |= 1u << (2 * i + 1);
    }
    if (c[1] != c[0] || c[2] != c[0]) used |= 1u << 6;
    enc.encodeSymbol(*m.rgb_used, used);
    std::int32_t d_lo = 0, d_hi = 0;
    if (used & 1) {
      d_lo = lo(c[0]) - lo(last[0]);
      enc.encodeSymbol(*m.rgb_diff[0], std::uint32_t(d_lo) & 0xFF);
    }
    if (used & 2) {
      d_hi = hi(c[0]) - hi(last[0]);
      enc.encodeSymbol(*m.rgb_diff[1], std::uint32_t(d_hi) & 0xFF);
    }
    if (used & (1u << 6)) {
      if (used & (1u << 2)) {
        const std::int32_t corr = lo(c[1]) - std::int32_t(clampByte(d_lo + lo(last[1])));
        enc.encodeSymbol(*m.rgb_diff[2], std::uint32_t(corr) & 0xFF);
      }
      if (used & (1u << 4)) {
        d_lo = (d_lo + lo(c[1]) - lo(last[1])) / 2;
        const std::int32_t corr = lo(c[2]) - std::int32_t(clampByte(d_lo + lo(last[2])));
        enc.encodeSymbol(*m.rgb_diff[4], std::uint32_t(corr) & 0xFF);
      }
      if (used & (1u << 3)) {
        const std::int32_t corr = hi(c[1]) - std::int32_t(clampByte(d_hi + hi(last[1])));
        enc.encodeSymbol(*m.rgb_diff[3], std::uint32_t(corr) & 0xFF);
      }
      if (used & (1u << 5)) {
        d_hi = (d_hi + hi(c[1]) - hi(last[1])) / 2;
        const std::int32_t corr = hi(c[2]) - std::int32_t(clampByte(d_hi + hi(last[2])));
        enc.encodeSymbol(*m.rgb_diff[5], std::uint32_t(corr) & 0xFF);
      }
    }
    if (used != 0) rgb_changed_ = true;
    if (nir_) {
      std::uint32_t nir_used = 0;
      if (lo(c[3]) != lo(last[3])) nir_used |= 1;
      if (hi(c[3]) != hi(last[3])) nir_used |= 2;
      ArithmeticEncoder& nenc = nir_layer_.encoder;
      nenc.encodeSymbol(*m.nir_used, nir_used);
      if (nir_used & 1)
        nenc.encodeSymbol(*m.nir_diff[0], std::uint32_t(lo(c[3]) - lo(last[3])) & 0xFF);
      if (nir_used & 2)
        nenc.encodeSymbol(*m.nir_diff[1], std::uint32_t(hi(c[3]) - hi(last[3])) & 0xFF);
      if (nir_used != 0) nir_changed_ = true;
    }
    last = c;
  }

 private:
  LayerStream rgb_, nir_layer_;
  bool rgb_changed_ = false, nir_changed_ = false;
};

}  // namespace

std::unique_ptr<ItemDecoder> makeRgbDecoder(bool nir, unsigned version) {
  return std::make_unique<RgbDecoder>(nir, version);
}
std::unique_ptr<ItemEncoder> makeRgbEncoder(bool nir, unsigned version) {
  return std::make_unique<RgbEncoder>(nir, version);
}

}  // namespace parallax::laz::layered
