// GPSTIME11: the 8-byte GPS time of point formats 1, 3, 4 and 5.
//
// The double is coded through its 64-bit pattern: for a regularly firing scanner the integer
// difference between consecutive times is nearly constant, so the codec predicts the difference
// as a multiple of the last one (Isenburg 2013, "Compressing GPS times"). A symbol gives the
// multiplier (1 the common case, 0 a much smaller step, negative ones for time going back,
// "unchanged", "a 64-bit jump"); the integer coder codes the rest in a context per kind of
// multiplier. Version 2 also keeps four time sequences at once (scanners that interleave
// pulses of several mirrors or channels): a symbol switches between them, and a jump that fits
// none starts a new one.
//
// The writer's multiplier is a float division rounded to an integer, as LASzip computes it
// (including what x86 gives for a float beyond the int32 range): the decoder never needs it,
// but the same multiplier is what makes the encoder's output byte for byte LASzip's.
#include <cassert>
#include <cmath>
#include <limits>

#include "io/laz/integer_codec.h"
#include "io/laz/pointwise_items.h"

namespace parallax::laz::pointwise {
namespace {

const IntegerCodecShape kTimeV2{.bits = 32, .contexts = 9};
const IntegerCodecShape kTimeV1{.bits = 32, .contexts = 6};

// Version 2's multiplier symbols: 1..499 multiples, 500 "500 or more", 501..509 the negative
// multiples -1..-9, 510 "-10 or less", 511 unchanged, 512 a new sequence, 513-515 a switch to
// the sequence 1-3 ahead; 0 a step much smaller than the last.
constexpr std::int32_t kMulti = 500;
constexpr std::int32_t kMultiMinus = -10;
constexpr std::uint32_t kUnchanged = kMulti - kMultiMinus + 1;  // 511
constexpr std::uint32_t kCodeFull = kMulti - kMultiMinus + 2;   // 512
constexpr std::uint32_t kMultiSymbols = kMulti - kMultiMinus + 6;

// Version 1's: 0..508 multiples (509: "509 or more"), 510 a 64-bit jump, 511 unchanged.
constexpr std::uint32_t kMultiMaxV1 = 512;

// A float converted to int32 as x86's cvttss2si does it: out of range gives INT32_MIN.
std::int32_t truncateLikeX86(double value) {
  if (!(value > -2147483649.0 && value < 2147483648.0)) {
    return std::numeric_limits<std::int32_t>::min();
  }
  return std::int32_t(value);
}

// LASzip's I32_QUANTIZE of a float ratio: the float widened to double, +-0.5, truncated.
std::int32_t roundedRatio(std::int32_t diff, std::int32_t last_diff) {
  const float ratio = float(diff) / float(last_diff);
  return ratio >= 0 ? truncateLikeX86(double(ratio) + 0.5) : truncateLikeX86(double(ratio) - 0.5);
}

// A 64-bit difference that fits 32 bits, or nothing.
bool fits32(std::uint64_t a, std::uint64_t b, std::int32_t& diff) {
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

class GpsTimeEncoderV2 final : public ItemEncoder {
 public:
  void start(const std::byte* first) override {
    s_.reset(first);
    ic_.reset();
  }

  void encode(ArithmeticEncoder& enc, const std::byte* item) override {
    const std::uint64_t time = loadLe<std::uint64_t>(item);
    // At most one switch: after it the difference fits 32 bits.
    for (;;) {
      const bool zero = s_.last_diff[s_.last] == 0;
      SymbolModel& model = zero ? s_.zero_diff : s_.multi;
      if (time == s_.time[s_.last]) {
        enc.encodeSymbol(model, zero ? 0 : kUnchanged);
        return;
      }
      std::int32_t diff;
      if (fits32(time, s_.time[s_.last], diff)) {
        if (zero) {
          enc.encodeSymbol(model, 1);
          ic_.encode(enc, 0, diff, 0);
          s_.last_diff[s_.last] = diff;
          s_.extreme[s_.last] = 0;
        } else {
          encodeMultiple(enc, diff);
        }
        s_.time[s_.last] = time;
        return;
      }
      bool switched = false;
      for (unsigned i = 1; i < 4; ++i) {
        std::int32_t other;
        if (fits32(time, s_.time[(s_.last + i) & 3], other)) {
          enc.encodeSymbol(model, zero ? i + 2 : kCodeFull + i);
          s_.last = (s_.last + i) & 3;
          switched = true;
          break;
        }
      }
      if (switched) continue;
      enc.encodeSymbol(model, zero ? 2 : kCodeFull);
      ic_.encode(enc, std::int32_t(s_.time[s_.last] >> 32), std::int32_t(time >> 32), 8);
      enc.writeInt(std::uint32_t(time));
      s_.next = (s_.next + 1) & 3;
      s_.last = s_.next;
      s_.last_diff[s_.last] = 0;
      s_.extreme[s_.last] = 0;
      s_.time[s_.last] = time;
      return;
    }
  }

 private:
  void encodeMultiple(ArithmeticEncoder& enc, std::int32_t diff) {
    const std::int32_t last_diff = s_.last_diff[s_.last];
    const std::int32_t multi = roundedRatio(diff, last_diff);
    if (multi == 1) {
      enc.encodeSymbol(s_.multi, 1);
      ic_.encode(enc, last_diff, diff, 1);
      s_.extreme[s_.last] = 0;
    } else if (multi > 0) {
      if (multi < kMulti) {
        enc.encodeSymbol(s_.multi, std::uint32_t(multi));
        ic_.encode(enc, wrapMul(multi, last_diff), diff, multi < 10 ? 2 : 3);
      } else {
        enc.encodeSymbol(s_.multi, kMulti);
        ic_.encode(enc, wrapMul(kMulti, last_diff), diff, 4);
        s_.countExtreme(diff);
      }
    } else if (multi < 0) {
      if (multi > kMultiMinus) {
        enc.encodeSymbol(s_.multi, std::uint32_t(kMulti - multi));
        ic_.encode(enc, wrapMul(multi, last_diff), diff, 5);
      } else {
        enc.encodeSymbol(s_.multi, std::uint32_t(kMulti - kMultiMinus));
        ic_.encode(enc, wrapMul(kMultiMinus, last_diff), diff, 6);
        s_.countExtreme(diff);
      }
    } else {
      enc.encodeSymbol(s_.multi, 0);
      ic_.encode(enc, 0, diff, 7);
      s_.countExtreme(diff);
    }
  }

  StateV2<false> s_;
  IntegerEncoder ic_{kTimeV2};
};

// ---------------------------------------------------------------------------------------------
// Version 1: one sequence.

template <bool kDecoding>
struct StateV1 {
  std::uint64_t time = 0;
  std::int32_t last_diff = 0;
  std::int32_t extreme = 0;
  SymbolModel multi{kMultiMaxV1, kDecoding};
  SymbolModel zero_diff{3, kDecoding};

  void reset(const std::byte* first) {
    time = loadLe<std::uint64_t>(first);
    last_diff = 0;
    extreme = 0;
    multi.reset();
    zero_diff.reset();
  }
  void countExtreme(std::int32_t diff) {
    if (++extreme > 3) {
      last_diff = diff;
      extreme = 0;
    }
  }
};

std::uint32_t contextV1(std::int32_t multi) {
  return multi < 10 ? 3 : multi < 50 ? 4 : 5;
}

class GpsTimeDecoderV1 final : public ItemDecoder {
 public:
  void start(const std::byte* first) override {
    s_.reset(first);
    ic_.reset();
  }

  void decode(ArithmeticDecoder& dec, std::byte* out) override {
    if (s_.last_diff == 0) {
      const std::uint32_t multi = dec.decodeSymbol(s_.zero_diff);
      if (multi == 1) {
        s_.last_diff = ic_.decode(dec, 0, 0);
        s_.time += std::uint64_t(std::int64_t(s_.last_diff));
      } else if (multi == 2) {
        s_.time = dec.readInt64();
      }
    } else {
      const std::int32_t multi = std::int32_t(dec.decodeSymbol(s_.multi));
      if (multi < std::int32_t(kMultiMaxV1) - 2) {
        std::int32_t diff;
        if (multi == 1) {
          diff = ic_.decode(dec, s_.last_diff, 1);
          s_.last_diff = diff;
          s_.extreme = 0;
        } else if (multi == 0) {
          diff = ic_.decode(dec, s_.last_diff / 4, 2);
          s_.countExtreme(diff);
        } else {
          diff = ic_.decode(dec, wrapMul(multi, s_.last_diff), contextV1(multi));
          if (multi == std::int32_t(kMultiMaxV1) - 3) s_.countExtreme(diff);
        }
        s_.time += std::uint64_t(std::int64_t(diff));
      } else if (multi == std::int32_t(kMultiMaxV1) - 2) {
        s_.time = dec.readInt64();
      }
    }
    storeLe(out, s_.time);
  }

 private:
  StateV1<true> s_;
  IntegerDecoder ic_{kTimeV1};
};

class GpsTimeEncoderV1 final : public ItemEncoder {
 public:
  void start(const std::byte* first) override {
    s_.reset(first);
    ic_.reset();
  }

  void encode(ArithmeticEncoder& enc, const std::byte* item) override {
    const std::uint64_t time = loadLe<std::uint64_t>(item);
    if (s_.last_diff == 0) {
      if (time == s_.time) {
        enc.encodeSymbol(s_.zero_diff, 0);
        return;
      }
      std::int32_t diff;
      if (fits32(time, s_.time, diff)) {
        enc.encodeSymbol(s_.zero_diff, 1);
        ic_.encode(enc, 0, diff, 0);
        s_.last_diff = diff;
      } else {
        enc.encodeSymbol(s_.zero_diff, 2);
        enc.writeInt64(time);
      }
      s_.time = time;
      return;
    }
    if (time == s_.time) {
      enc.encodeSymbol(s_.multi, kMultiMaxV1 - 1);
      return;
    }
    std::int32_t diff;
    if (!fits32(time, s_.time, diff)) {
      enc.encodeSymbol(s_.multi, kMultiMaxV1 - 2);
      enc.writeInt64(time);
      s_.time = time;
      return;
    }
    // (int)(float ratio + 0.5f), clamped to 0..509 (x86's INT32_MIN for a ratio out of range
    // clamps to 0, as LASzip's writer gets on the machines it runs on).
    const float ratio = float(diff) / float(s_.last_diff) + 0.5f;
    std::int32_t multi = truncateLikeX86(double(ratio));
    const std::int32_t top = std::int32_t(kMultiMaxV1) - 3;
    multi = multi >= top ? top : multi <= 0 ? 0 : multi;
    enc.encodeSymbol(s_.multi, std::uint32_t(multi));
    if (multi == 1) {
      ic_.encode(enc, s_.last_diff, diff, 1);
      s_.last_diff = diff;
      s_.extreme = 0;
    } else if (multi == 0) {
      ic_.encode(enc, s_.last_diff / 4, diff, 2);
      s_.countExtreme(diff);
    } else {
      ic_.encode(enc, wrapMul(multi, s_.last_diff), diff, contextV1(multi));
      if (multi == top) s_.countExtreme(diff);
    }
    s_.time = time;
  }

 private:
  StateV1<false> s_;
  IntegerEncoder ic_{kTimeV1};
};

}  // namespace

std::unique_ptr<ItemDecoder> makeGpsTimeDecoder(int version) {
  assert((version == 1 || version == 2) && "GPSTIME11 has versions 1 and 2");
  if (version == 1) return std::make_unique<GpsTimeDecoderV1>();
  return std::make_unique<GpsTimeDecoderV2>();
}

std::unique_ptr<ItemEncoder> makeGpsTimeEncoder(int version) {
  assert((version == 1 || version == 2) && "GPSTIME11 has versions 1 and 2");
  if (version == 1) return std::make_unique<GpsTimeEncoderV1>();
  return std::make_unique<GpsTimeEncoderV2>();
}

}  // namespace parallax::laz::pointwise
