// GPSTIME11 version 2's state and decoder (see pointwise_gpstime.cpp for the format), in a header
// so that the specialised chunk decoders (pointwise_codec.cpp) call it directly, inlined, with no
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

namespace parallax::laz::pointwise::gpstime {

inline const IntegerCodecShape kTimeV2{.bits = 32, .contexts = 9};
inline const IntegerCodecShape kTimeV1{.bits = 32, .contexts = 6};

// Version 2's multiplier symbols: 1..499 multiples, 500 "500 or more", 501..509 the negative
// multiples -1..-9, 510 "-10 or less", 511 unchanged, 512 a new sequence, 513-515 a switch to
// the sequence 1-3 ahead; 0 a step much smaller than the last.
inline constexpr std::int32_t kMulti = 500;
inline constexpr std::int32_t kMultiMinus = -10;
inline constexpr std::uint32_t kUnchanged = kMulti - kMultiMinus + 1;  // 511
inline constexpr std::uint32_t kCodeFull = kMulti - kMultiMinus + 2;   // 512
inline constexpr std::uint32_t kMultiSymbols = kMulti - kMultiMinus + 6;

// Version 1's: 0..508 multiples (509: "509 or more"), 510 a 64-bit jump, 511 unchanged.
inline constexpr std::uint32_t kMultiMaxV1 = 512;

// A float converted to int32 as x86's cvttss2si does it: out of range gives INT32_MIN.
inline std::int32_t truncateLikeX86(double value) {
  if (!(value > -2147483649.0 && value < 2147483648.0)) {
    return std::numeric_limits<std::int32_t>::min();
  }
  return std::int32_t(value);
}

// LASzip's I32_QUANTIZE of a float ratio: the float widened to double, +-0.5, truncated.
inline std::int32_t roundedRatio(std::int32_t diff, std::int32_t last_diff) {
  const float ratio = float(diff) / float(last_diff);
  return ratio >= 0 ? truncateLikeX86(double(ratio) + 0.5) : truncateLikeX86(double(ratio) - 0.5);
}

// A 64-bit difference that fits 32 bits, or nothing.
inline bool fits32(std::uint64_t a, std::uint64_t b, std::int32_t& diff) {
  const std::int64_t d = std::int64_t(a - b);
  diff = std::int32_t(d);
  return d == std::int64_t(diff);
}

template <bool kDecoding>
struct StateV2 {
  std::array<std::uint64_t, 4> time{};  // the bit patterns of the four sequences' last times
  std::array<std::int32_t, 4> last_diff{};
  std::array<std::int32_t, 4> extreme{};  // consecutive extreme multipliers per sequence
  unsigned last = 0, next = 0;
  SymbolModel multi{kMultiSymbols, kDecoding};
  SymbolModel zero_diff{6, kDecoding};

  void reset(const std::byte* first) {
    time = {loadLe<std::uint64_t>(first), 0, 0, 0};
    last_diff.fill(0);
    extreme.fill(0);
    last = next = 0;
    multi.reset();
    zero_diff.reset();
  }
  void add(std::int32_t diff) { time[last] += std::uint64_t(std::int64_t(diff)); }
  // After an extreme multiplier: four in a row make the last step the new reference.
  void countExtreme(std::int32_t diff) {
    if (++extreme[last] > 3) {
      last_diff[last] = diff;
      extreme[last] = 0;
    }
  }
};

class GpsTimeDecoderV2 final : public ItemDecoder {
 public:
  void start(const std::byte* first) override {
    s_.reset(first);
    ic_.reset();
  }

  void decode(ArithmeticDecoder& dec, std::byte* out) override {
    // A valid stream switches sequence at most once per point; a corrupt one may ask again and
    // again, so the loop is bounded (the chunk check then reports the stream).
    for (int hop = 0; hop < 4; ++hop) {
      if (s_.last_diff[s_.last] == 0) {
        const std::uint32_t multi = dec.decodeSymbol(s_.zero_diff);
        if (multi == 0) break;  // unchanged
        if (multi == 1) {
          s_.last_diff[s_.last] = ic_.decode(dec, 0, 0);
          s_.add(s_.last_diff[s_.last]);
          s_.extreme[s_.last] = 0;
          break;
        }
        if (multi == 2) {
          startSequence(dec);
          break;
        }
        s_.last = (s_.last + multi - 2) & 3;
        continue;
      }
      const std::uint32_t multi = dec.decodeSymbol(s_.multi);
      if (multi == 1) {
        s_.add(ic_.decode(dec, s_.last_diff[s_.last], 1));
        s_.extreme[s_.last] = 0;
      } else if (multi < kUnchanged) {
        s_.add(decodeMultiple(dec, std::int32_t(multi)));
      } else if (multi == kCodeFull) {
        startSequence(dec);
      } else if (multi > kCodeFull) {
        s_.last = (s_.last + multi - kCodeFull) & 3;
        continue;
      }
      break;  // kUnchanged included
    }
    storeLe(out, s_.time[s_.last]);
  }

 private:
  std::int32_t decodeMultiple(ArithmeticDecoder& dec, std::int32_t multi) {
    const std::int32_t last_diff = s_.last_diff[s_.last];
    if (multi == 0) {
      const std::int32_t diff = ic_.decode(dec, 0, 7);
      s_.countExtreme(diff);
      return diff;
    }
    if (multi < kMulti) return ic_.decode(dec, wrapMul(multi, last_diff), multi < 10 ? 2 : 3);
    if (multi == kMulti) {
      const std::int32_t diff = ic_.decode(dec, wrapMul(kMulti, last_diff), 4);
      s_.countExtreme(diff);
      return diff;
    }
    multi = kMulti - multi;  // -1 .. -10
    if (multi > kMultiMinus) return ic_.decode(dec, wrapMul(multi, last_diff), 5);
    const std::int32_t diff = ic_.decode(dec, wrapMul(kMultiMinus, last_diff), 6);
    s_.countExtreme(diff);
    return diff;
  }
  // A jump no sequence covers: the high 32 bits predicted by the current sequence's, the low 32
  // bits raw, into the next of the four slots.
  void startSequence(ArithmeticDecoder& dec) {
    s_.next = (s_.next + 1) & 3;
    const std::uint32_t high =
        std::uint32_t(ic_.decode(dec, std::int32_t(s_.time[s_.last] >> 32), 8));
    s_.time[s_.next] = (std::uint64_t(high) << 32) | dec.readInt();
    s_.last = s_.next;
    s_.last_diff[s_.last] = 0;
    s_.extreme[s_.last] = 0;
  }

  StateV2<true> s_;
  IntegerDecoder ic_{kTimeV2};
};

}  // namespace parallax::laz::pointwise::gpstime
