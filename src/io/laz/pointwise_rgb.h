// RGB12 version 2's state and decoder (see pointwise_rgb.cpp for the format), in a header so
// that the specialised chunk decoders (pointwise_codec.cpp) call it directly, inlined, with no
// virtual call per point. Internal to io/laz.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "io/laz/integer_codec.h"
#include "io/laz/pointwise_items.h"

namespace parallax::laz::pointwise::rgb {

struct Rgb {
  std::uint16_t c[3];
};
static_assert(sizeof(Rgb) == 6, "Rgb mirrors the 6-byte item");

inline unsigned lo(std::uint16_t v) {
  return v & 0xFFu;
}
inline unsigned hi(std::uint16_t v) {
  return v >> 8;
}
inline unsigned clampByte(int v) {
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

}  // namespace parallax::laz::pointwise::rgb
