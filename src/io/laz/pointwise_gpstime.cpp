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
#include "io/laz/pointwise_gpstime.h"
#include "io/laz/pointwise_items.h"

namespace parallax::laz::pointwise {

// The coders live in the item's namespace (not a using-directive: in a unity batch one would
// reach the other items' sources too).
namespace gpstime {
namespace {

class GpsTimeEncoderV2 final : public ItemEncoder {
 public:
  void start(const std::byte* first) override {
    s_.reset(first);
    ic_.reset();
  }

  void encode(ArithmeticEncoder& enc, const std::byte* item) override {
    const std::uint64_t time = loadLE<std::uint64_t>(item);
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
    time = loadLE<std::uint64_t>(first);
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
    storeLE(out, s_.time);
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
    const std::uint64_t time = loadLE<std::uint64_t>(item);
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
}  // namespace gpstime

std::unique_ptr<ItemDecoder> makeGpsTimeDecoder(int version) {
  assert((version == 1 || version == 2) && "GPSTIME11 has versions 1 and 2");
  if (version == 1) return std::make_unique<gpstime::GpsTimeDecoderV1>();
  return std::make_unique<gpstime::GpsTimeDecoderV2>();
}

std::unique_ptr<ItemEncoder> makeGpsTimeEncoder(int version) {
  assert((version == 1 || version == 2) && "GPSTIME11 has versions 1 and 2");
  if (version == 1) return std::make_unique<gpstime::GpsTimeEncoderV1>();
  return std::make_unique<gpstime::GpsTimeEncoderV2>();
}

}  // namespace parallax::laz::pointwise
