// The LAZ entropy layer: arithmetic coder, adaptive models and the integer codec. Streams encoded
// here must decode to exactly what went in, for every kind of symbol the point codecs use, and a
// corrupt or truncated stream must be flagged, never crash or hang. (The bit-exact agreement with
// LASzip's writer is checked by the LAZ reader's tests on real files.)
#include <gtest/gtest.h>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "io/laz/arithmetic_decoder.h"
#include "io/laz/arithmetic_encoder.h"
#include "io/laz/integer_codec.h"

namespace parallax::laz {
namespace {

std::span<const std::byte> bytesOf(const std::vector<std::uint8_t>& v) {
  return std::as_bytes(std::span(v));
}

// One mixed stream: what each step codes, so encode and decode walk the same script.
struct Step {
  enum Kind { Bit, Symbol, Raw, Integer } kind;
  std::uint32_t model;  // which model / codec
  std::uint32_t bits;   // Raw: bit count
  std::int32_t value;
  std::int32_t prediction;
  std::uint32_t context;
};

struct Models {
  std::vector<BitModel> bits{3};
  std::vector<SymbolModel> symbols;
  explicit Models(bool decoding) {
    for (std::uint32_t n : {2u, 5u, 16u, 17u, 64u, 256u, 2048u}) symbols.emplace_back(n, decoding);
  }
};

const std::vector<IntegerCodecShape> kShapes = {
    {.bits = 32, .contexts = 1},                                 // positions: 32-bit, wrapping
    {.bits = 16, .contexts = 4},                                 // intensity-like, several contexts
    {.bits = 8, .contexts = 2, .bits_high = 8},                  // bytes
    {.bits = 16, .contexts = 1, .bits_high = 8, .range = 1000},  // a range not a power of two
    {.bits = 32, .contexts = 2, .bits_high = 4},                 // large k in two steps
};

std::vector<Step> makeScript(std::uint32_t seed, std::size_t n) {
  std::mt19937 rng(seed);
  std::vector<Step> script;
  const std::uint32_t symbol_sizes[] = {2, 5, 16, 17, 64, 256, 2048};
  for (std::size_t i = 0; i < n; ++i) {
    Step s{};
    s.kind = Step::Kind(rng() % 4);
    switch (s.kind) {
      case Step::Bit:
        s.model = rng() % 3;
        // Skewed bits, so the models really adapt.
        s.value = (rng() % 10) < (s.model + 1) * 3 ? 1 : 0;
        break;
      case Step::Symbol: {
        s.model = rng() % 7;
        // Mostly small symbols (geometric), sometimes any.
        std::uint32_t v =
            (rng() % 4 == 0) ? rng() : std::uint32_t(std::countr_zero(rng() | 1u << 20));
        s.value = std::int32_t(v % symbol_sizes[s.model]);
        break;
      }
      case Step::Raw:
        s.bits = 1 + rng() % 32;
        s.value = std::int32_t(s.bits == 32 ? rng() : rng() & ((1u << s.bits) - 1));
        break;
      case Step::Integer: {
        s.model = rng() % std::uint32_t(kShapes.size());
        const IntegerCodecShape& shape = kShapes[s.model];
        s.context = rng() % shape.contexts;
        if (shape.range != 0) {
          s.value = std::int32_t(rng() % shape.range);
          s.prediction = std::int32_t(rng() % shape.range);
        } else if (shape.bits == 32) {
          // Small differences mostly; sometimes the extremes (INT32_MIN correctors).
          s.prediction = std::int32_t(rng());
          const int spread = int(rng() % 24);
          s.value =
              std::int32_t(std::uint32_t(s.prediction) +
                           std::uint32_t(std::int32_t(rng() % (2u << spread)) - (1 << spread)));
          if (rng() % 50 == 0) s.value = std::int32_t(std::uint32_t(s.prediction) + 0x80000000u);
        } else {
          const std::uint32_t mask = (1u << shape.bits) - 1;
          s.value = std::int32_t(rng() & mask);
          s.prediction = std::int32_t((std::uint32_t(s.value) + (rng() % 7) - 3) & mask);
        }
        break;
      }
    }
    script.push_back(s);
  }
  return script;
}

std::vector<std::uint8_t> encode(const std::vector<Step>& script) {
  std::vector<std::uint8_t> out;
  ArithmeticEncoder enc(out);
  Models m(false);
  std::vector<IntegerEncoder> ints;
  for (const auto& shape : kShapes) ints.emplace_back(shape);
  for (const Step& s : script) {
    switch (s.kind) {
      case Step::Bit:
        enc.encodeBit(m.bits[s.model], std::uint32_t(s.value));
        break;
      case Step::Symbol:
        enc.encodeSymbol(m.symbols[s.model], std::uint32_t(s.value));
        break;
      case Step::Raw:
        enc.writeBits(s.bits, std::uint32_t(s.value));
        break;
      case Step::Integer:
        ints[s.model].encode(enc, s.prediction, s.value, s.context);
        break;
    }
  }
  enc.finish();
  return out;
}

TEST(LazEntropy, MixedStreamRoundTrips) {
  for (std::uint32_t seed : {1u, 2u, 3u, 4u}) {
    const std::vector<Step> script = makeScript(seed, 50'000);
    const std::vector<std::uint8_t> bytes = encode(script);
    ArithmeticDecoder dec;
    dec.start(bytesOf(bytes));
    Models m(true);
    std::vector<IntegerDecoder> ints;
    for (const auto& shape : kShapes) ints.emplace_back(shape);
    for (std::size_t i = 0; i < script.size(); ++i) {
      const Step& s = script[i];
      std::int32_t got = 0;
      switch (s.kind) {
        case Step::Bit:
          got = std::int32_t(dec.decodeBit(m.bits[s.model]));
          break;
        case Step::Symbol:
          got = std::int32_t(dec.decodeSymbol(m.symbols[s.model]));
          break;
        case Step::Raw:
          got = std::int32_t(dec.readBits(s.bits));
          break;
        case Step::Integer:
          got = ints[s.model].decode(dec, s.prediction, s.context);
          break;
      }
      ASSERT_EQ(got, s.value) << "seed " << seed << ", step " << i << ", kind " << int(s.kind);
    }
    EXPECT_TRUE(dec.ok());
    // The decoder consumes exactly the encoder's bytes: no more (it would read past a chunk),
    // no fewer (the stream would carry dead bytes).
    EXPECT_EQ(dec.consumed(bytesOf(bytes)), bytes.size()) << "seed " << seed;
  }
}

TEST(LazEntropy, EncoderAndDecoderAgreeOnK) {
  // The point codecs use the k of one field as a context for the next: both sides must see
  // the same k for the same value.
  IntegerEncoder ie({.bits = 32});
  IntegerDecoder id({.bits = 32});
  std::vector<std::uint8_t> out;
  ArithmeticEncoder enc(out);
  const std::int32_t values[] = {0, 1, -1, 2, 3, -4, 1000, -1000, 1 << 20, INT32_MIN, INT32_MAX};
  std::vector<std::uint32_t> ks;
  for (std::int32_t v : values) {
    ie.encode(enc, 0, v);
    ks.push_back(ie.lastK());
  }
  enc.finish();
  ArithmeticDecoder dec;
  dec.start(bytesOf(out));
  for (std::size_t i = 0; i < std::size(values); ++i) {
    EXPECT_EQ(id.decode(dec, 0), values[i]);
    EXPECT_EQ(id.lastK(), ks[i]) << "value " << values[i];
  }
  // k of 0 and 1 is 0; of 2 and -1 is 1; of INT32_MIN (|c| = 2^31) is 32.
  EXPECT_EQ(ks[0], 0u);
  EXPECT_EQ(ks[1], 0u);
  EXPECT_EQ(ks[2], 1u);
  EXPECT_EQ(ks[3], 1u);
  EXPECT_EQ(ks[9], 32u);
}

TEST(LazEntropy, ModelsResetToTheirInitialState) {
  // A chunk restarts every model: after reset() a stream codes as from fresh models.
  const std::vector<Step> script = makeScript(7, 2000);
  const std::vector<std::uint8_t> fresh = encode(script);
  std::vector<std::uint8_t> out;
  Models m(false);
  for (int round = 0; round < 2; ++round) {
    for (BitModel& b : m.bits) b.reset();
    for (SymbolModel& s : m.symbols) s.reset();
    out.clear();
    ArithmeticEncoder e(out);
    std::vector<IntegerEncoder> ints;
    for (const auto& shape : kShapes) ints.emplace_back(shape);
    for (const Step& s : script) {
      switch (s.kind) {
        case Step::Bit:
          e.encodeBit(m.bits[s.model], std::uint32_t(s.value));
          break;
        case Step::Symbol:
          e.encodeSymbol(m.symbols[s.model], std::uint32_t(s.value));
          break;
        case Step::Raw:
          e.writeBits(s.bits, std::uint32_t(s.value));
          break;
        case Step::Integer:
          ints[s.model].encode(e, s.prediction, s.value, s.context);
          break;
      }
    }
    e.finish();
    EXPECT_EQ(out, fresh) << "round " << round;
  }
}

TEST(LazEntropy, EmptyStreamFinishesWithFourBytes) {
  // The termination writes exactly the four bytes the decoder reads at its start.
  std::vector<std::uint8_t> out;
  ArithmeticEncoder enc(out);
  EXPECT_EQ(enc.finish(), 4u);
  ArithmeticDecoder dec;
  dec.start(bytesOf(out));
  EXPECT_TRUE(dec.ok());
  EXPECT_EQ(dec.consumed(bytesOf(out)), 4u);
}

TEST(LazEntropy, TruncatedStreamIsFlagged) {
  const std::vector<Step> script = makeScript(11, 5000);
  std::vector<std::uint8_t> bytes = encode(script);
  bytes.resize(bytes.size() / 2);
  ArithmeticDecoder dec;
  dec.start(bytesOf(bytes));
  Models m(true);
  std::vector<IntegerDecoder> ints;
  for (const auto& shape : kShapes) ints.emplace_back(shape);
  for (const Step& s : script) {
    switch (s.kind) {
      case Step::Bit:
        dec.decodeBit(m.bits[s.model]);
        break;
      case Step::Symbol:
        dec.decodeSymbol(m.symbols[s.model]);
        break;
      case Step::Raw:
        dec.readBits(s.bits);
        break;
      case Step::Integer:
        ints[s.model].decode(dec, s.prediction, s.context);
        break;
    }
  }
  EXPECT_TRUE(dec.overran());
  EXPECT_FALSE(dec.ok());
}

TEST(LazEntropy, GarbageNeverCrashes) {
  // Random bytes decode to something (flagged or not), within bounds, in bounded time.
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<std::uint8_t> bytes(rng() % 64);
    for (auto& b : bytes) b = std::uint8_t(rng());
    ArithmeticDecoder dec;
    dec.start(bytesOf(bytes));
    Models m(true);
    IntegerDecoder id({.bits = 32, .contexts = 2, .bits_high = 4});
    for (int i = 0; i < 500; ++i) {
      const std::uint32_t model = rng() % 7;
      ASSERT_LT(dec.decodeSymbol(m.symbols[model]), m.symbols[model].symbols());
      ASSERT_LE(dec.decodeBit(m.bits[0]), 1u);
      ASSERT_LT(dec.readBits(5), 32u);
      id.decode(dec, std::int32_t(rng()), rng() % 2);
    }
    EXPECT_TRUE(dec.overran()) << "trial " << trial;  // 500 steps need more than 64 bytes
  }
}

}  // namespace
}  // namespace parallax::laz
