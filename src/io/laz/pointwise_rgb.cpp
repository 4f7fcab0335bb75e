// RGB12: the three 16-bit colour channels of point formats 2, 3 and 5.
//
// Each channel is two bytes, coded separately (8-bit colours scaled to 16 bits repeat the
// byte; 8-bit colours stored as they are leave the high byte zero). Version 2 (Isenburg 2013):
// a 7-bit symbol says which of the six bytes changed, and whether the colour is grey (bit 6 clear:
// green and blue equal red). Red's bytes are coded as differences to the last red; green's
// predicted by the last green moved by red's change, blue's by the last blue moved by the mean
// of red's and green's changes, each clamped to a byte (the clamping is the format's).
// Version 1: a 6-bit change symbol, then each changed byte through an 8-bit integer coder.
#include <algorithm>
#include <cassert>

#include "io/laz/integer_codec.h"
#include "io/laz/pointwise_items.h"
#include "io/laz/pointwise_rgb.h"

namespace parallax::laz::pointwise {

// The coders live in the item's namespace (not a using-directive: in a unity batch one would
// reach the other items' sources too).
namespace rgb {
namespace {

class RgbEncoderV2 final : public ItemEncoder {
 public:
  void start(const std::byte* first) override { s_.reset(first); }

  void encode(ArithmeticEncoder& enc, const std::byte* item) override {
    Rgb p;
    std::memcpy(&p, item, sizeof p);
    const Rgb& last = s_.last;
    std::uint32_t used = 0;
    for (int c = 0; c < 3; ++c) {
      if (lo(last.c[c]) != lo(p.c[c])) used |= 1u << (2 * c);
      if (hi(last.c[c]) != hi(p.c[c])) used |= 2u << (2 * c);
    }
    if (p.c[0] != p.c[1] || p.c[0] != p.c[2]) used |= 64;
    enc.encodeSymbol(s_.used, used);
    auto put = [&](int model, int value) {
      enc.encodeSymbol(s_.diff[std::size_t(model)], std::uint32_t(value) & 0xFFu);
    };
    int diff_lo = 0, diff_hi = 0;
    if (used & 1) {
      diff_lo = int(lo(p.c[0])) - int(lo(last.c[0]));
      put(0, diff_lo);
    }
    if (used & 2) {
      diff_hi = int(hi(p.c[0])) - int(hi(last.c[0]));
      put(1, diff_hi);
    }
    if (used & 64) {
      if (used & 4) put(2, int(lo(p.c[1])) - int(clampByte(diff_lo + int(lo(last.c[1])))));
      if (used & 16) {
        diff_lo = (diff_lo + int(lo(p.c[1])) - int(lo(last.c[1]))) / 2;
        put(4, int(lo(p.c[2])) - int(clampByte(diff_lo + int(lo(last.c[2])))));
      }
      if (used & 8) put(3, int(hi(p.c[1])) - int(clampByte(diff_hi + int(hi(last.c[1])))));
      if (used & 32) {
        diff_hi = (diff_hi + int(hi(p.c[1])) - int(hi(last.c[1]))) / 2;
        put(5, int(hi(p.c[2])) - int(clampByte(diff_hi + int(hi(last.c[2])))));
      }
    }
    s_.last = p;
  }

 private:
  StateV2<false> s_;
};

const IntegerCodecShape kRgbV1{.bits = 8, .contexts = 6};

class RgbDecoderV1 final : public ItemDecoder {
 public:
  void start(const std::byte* first) override {
    std::memcpy(&last_, first, sizeof last_);
    used_.reset();
    ic_.reset();
  }

  void decode(ArithmeticDecoder& dec, std::byte* out) override {
    const std::uint32_t used = dec.decodeSymbol(used_);
    for (int c = 0; c < 3; ++c) {
      unsigned l = lo(last_.c[c]), h = hi(last_.c[c]);
      if (used & (1u << (2 * c))) l = unsigned(ic_.decode(dec, std::int32_t(l), 2u * c)) & 0xFFu;
      if (used & (2u << (2 * c))) {
        h = unsigned(ic_.decode(dec, std::int32_t(h), 2u * c + 1)) & 0xFFu;
      }
      last_.c[c] = std::uint16_t(l | (h << 8));
    }
    std::memcpy(out, &last_, sizeof last_);
  }

 private:
  Rgb last_{};
  SymbolModel used_{64, true};
  IntegerDecoder ic_{kRgbV1};
};

class RgbEncoderV1 final : public ItemEncoder {
 public:
  void start(const std::byte* first) override {
    std::memcpy(&last_, first, sizeof last_);
    used_.reset();
    ic_.reset();
  }

  void encode(ArithmeticEncoder& enc, const std::byte* item) override {
    Rgb p;
    std::memcpy(&p, item, sizeof p);
    std::uint32_t used = 0;
    for (int c = 0; c < 3; ++c) {
      if (lo(last_.c[c]) != lo(p.c[c])) used |= 1u << (2 * c);
      if (hi(last_.c[c]) != hi(p.c[c])) used |= 2u << (2 * c);
    }
    enc.encodeSymbol(used_, used);
    for (int c = 0; c < 3; ++c) {
      if (used & (1u << (2 * c))) {
        ic_.encode(enc, std::int32_t(lo(last_.c[c])), std::int32_t(lo(p.c[c])), 2u * c);
      }
      if (used & (2u << (2 * c))) {
        ic_.encode(enc, std::int32_t(hi(last_.c[c])), std::int32_t(hi(p.c[c])), 2u * c + 1);
      }
    }
    last_ = p;
  }

 private:
  Rgb last_{};
  SymbolModel used_{64, false};
  IntegerEncoder ic_{kRgbV1};
};

}  // namespace
}  // namespace rgb

std::unique_ptr<ItemDecoder> makeRgbDecoder(int version) {
  assert((version == 1 || version == 2) && "RGB12 has versions 1 and 2");
  if (version == 1) return std::make_unique<rgb::RgbDecoderV1>();
  return std::make_unique<rgb::RgbDecoderV2>();
}

std::unique_ptr<ItemEncoder> makeRgbEncoder(int version) {
  assert((version == 1 || version == 2) && "RGB12 has versions 1 and 2");
  if (version == 1) return std::make_unique<rgb::RgbEncoderV1>();
  return std::make_unique<rgb::RgbEncoderV2>();
}

}  // namespace parallax::laz::pointwise
