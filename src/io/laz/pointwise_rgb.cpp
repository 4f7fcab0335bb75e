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

namespace parallax::laz::pointwise {
namespace {

struct Rgb {
  std::uint16_t c[3];
};
static_assert(sizeof(Rgb) == 6, "Rgb mirrors the 6-byte item");

unsigned lo(std::uint16_t v) {
  return v & 0xFFu;
}
unsigned hi(std::uint16_t v) {
  return v >> 8;
}
unsigned clampByte(int v) {
  return unsigned(std::clamp(v, 0, 255));
}

template <bool kDecoding>
struct StateV2 {
  Rgb last{};
  SymbolModel used{128, kDecoding};
  std::array<SymbolModel, 6> diff{SymbolModel(256, kDecoding), SymbolModel(256, kDecoding),
                                  SymbolModel(256, kDecoding), SymbolModel(256, kDecoding),
                                  SymbolModel(256, kDecoding), SymbolModel(256, kDecoding)};
  void reset(const std::byte* first) {
    std::memcpy(&last, first, sizeof last);
    used.reset();
    for (SymbolModel& m : diff) m.reset();
  }
};

class RgbDecoderV2 final : public ItemDecoder {
 public:
  void start(const std::byte* first) override { s_.reset(first); }

  void decode(ArithmeticDecoder& dec, std::byte* out) override {
    const Rgb& last = s_.last;
    Rgb p;
    const std::uint32_t used = dec.decodeSymbol(s_.used);
    auto byteOf = [&](std::uint32_t bit, int model, unsigned predicted, unsigned last_byte) {
      return (used & bit) ? (dec.decodeSymbol(s_.diff[std::size_t(model)]) + predicted) & 0xFFu
                          : last_byte;
    };
    unsigned r_lo = byteOf(1, 0, lo(last.c[0]), lo(last.c[0]));
    unsigned r_hi = byteOf(2, 1, hi(last.c[0]), hi(last.c[0]));
    p.c[0] = std::uint16_t(r_lo | (r_hi << 8));
    if (used & 64) {
      int diff = int(r_lo) - int(lo(last.c[0]));
      const unsigned g_lo = byteOf(4, 2, clampByte(diff + int(lo(last.c[1]))), lo(last.c[1]));
      unsigned b_lo = lo(last.c[2]);
      if (used & 16) {
        diff = (diff + (int(g_lo) - int(lo(last.c[1])))) / 2;
        b_lo = byteOf(16, 4, clampByte(diff + int(lo(last.c[2]))), 0);
      }
      diff = int(r_hi) - int(hi(last.c[0]));
      const unsigned g_hi = byteOf(8, 3, clampByte(diff + int(hi(last.c[1]))), hi(last.c[1]));
      unsigned b_hi = hi(last.c[2]);
      if (used & 32) {
        diff = (diff + (int(g_hi) - int(hi(last.c[1])))) / 2;
        b_hi = byteOf(32, 5, clampByte(diff + int(hi(last.c[2]))), 0);
      }
      p.c[1] = std::uint16_t(g_lo | (g_hi << 8));
      p.c[2] = std::uint16_t(b_lo | (b_hi << 8));
    } else {
      p.c[1] = p.c[2] = p.c[0];
    }
    s_.last = p;
    std::memcpy(out, &p, sizeof p);
  }

 private:
  StateV2<true> s_;
};

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

std::unique_ptr<ItemDecoder> makeRgbDecoder(int version) {
  assert((version == 1 || version == 2) && "RGB12 has versions 1 and 2");
  if (version == 1) return std::make_unique<RgbDecoderV1>();
  return std::make_unique<RgbDecoderV2>();
}

std::unique_ptr<ItemEncoder> makeRgbEncoder(int version) {
  assert((version == 1 || version == 2) && "RGB12 has versions 1 and 2");
  if (version == 1) return std::make_unique<RgbEncoderV1>();
  return std::make_unique<RgbEncoderV2>();
}

}  // namespace parallax::laz::pointwise
