#include "io/laz/integer_codec.h"

#include <cassert>
#include <limits>

namespace parallax::laz {

IntegerModels::IntegerModels(const IntegerCodecShape& shape, bool for_decoding)
    : bits_high(shape.bits_high) {
  assert(shape.contexts >= 1 && "an integer codec needs at least one context");
  if (shape.range != 0) {
    // The corrector needs the bits of the range, one fewer when the range is a power of two.
    std::uint32_t r = shape.range;
    corr_bits = 0;
    while (r != 0) {
      r >>= 1;
      ++corr_bits;
    }
    corr_range = shape.range;
    if (corr_range == (1u << (corr_bits - 1))) --corr_bits;
    corr_min = -std::int32_t(corr_range / 2);
    corr_max = std::int32_t(std::int64_t(corr_min) + corr_range - 1);
  } else if (shape.bits != 0 && shape.bits < 32) {
    corr_bits = shape.bits;
    corr_range = 1u << shape.bits;
    corr_min = -std::int32_t(corr_range / 2);
    corr_max = std::int32_t(std::int64_t(corr_min) + corr_range - 1);
  } else {
    corr_bits = 32;
    corr_range = 0;
    corr_min = std::numeric_limits<std::int32_t>::min();
    corr_max = std::numeric_limits<std::int32_t>::max();
  }
  k_models.reserve(shape.contexts);
  for (std::uint32_t i = 0; i < shape.contexts; ++i) {
    k_models.emplace_back(corr_bits + 1, for_decoding);
  }
  corrector.reserve(corr_bits);
  for (std::uint32_t k = 1; k <= corr_bits; ++k) {
    corrector.emplace_back(1u << (k <= bits_high ? k : bits_high), for_decoding);
  }
  // Models are built in their initial state: generation 0 is the current one.
  k_generation.assign(k_models.size(), 0);
  corrector_generation.assign(corrector.size(), 0);
}

void IntegerModels::reset() {
  ++generation_;
  corrector0.reset();
}

std::int32_t IntegerDecoder::readCorrector(ArithmeticDecoder& dec, SymbolModel& k_model) {
  k_ = dec.decodeSymbol(k_model);
  if (k_ == 0) return std::int32_t(dec.decodeBit(models_.corrector0));  // c is 0 or 1
  if (k_ >= 32) return models_.corr_min;
  SymbolModel& model = models_.correctorModel(k_);
  std::int64_t c;
  if (k_ <= models_.bits_high) {
    c = dec.decodeSymbol(model);
  } else {
    const std::uint32_t low_bits = k_ - models_.bits_high;
    const std::uint32_t high = dec.decodeSymbol(model);
    c = (std::int64_t(high) << low_bits) | dec.readBits(low_bits);
  }
  // k selects [-(2^k - 1), -2^(k-1)] or [2^(k-1) + 1, 2^k]; c is the offset inside them.
  if (c >= (std::int64_t(1) << (k_ - 1))) {
    c += 1;
  } else {
    c -= (std::int64_t(1) << k_) - 1;
  }
  return std::int32_t(c);
}

std::int32_t IntegerDecoder::decode(ArithmeticDecoder& dec, std::int32_t prediction,
                                    std::uint32_t context) {
  const std::int32_t c = readCorrector(dec, models_.kModel(context));
  // Wrap into [0, range): unsigned arithmetic, as the 32-bit case wraps modulo 2^32.
  std::uint32_t real = std::uint32_t(prediction) + std::uint32_t(c);
  if (std::int32_t(real) < 0) {
    real += models_.corr_range;
  } else if (real >= models_.corr_range && models_.corr_range != 0) {
    real -= models_.corr_range;
  }
  return std::int32_t(real);
}

void IntegerEncoder::writeCorrector(ArithmeticEncoder& enc, std::int32_t c, SymbolModel& k_model) {
  // k: significant bits of |c| for c <= 0, of c - 1 for c > 0.
  std::uint32_t magnitude = c <= 0 ? 0u - std::uint32_t(c) : std::uint32_t(c) - 1;
  k_ = 0;
  while (magnitude != 0) {
    magnitude >>= 1;
    ++k_;
  }
  enc.encodeSymbol(k_model, k_);
  if (k_ == 0) {
    enc.encodeBit(models_.corrector0, std::uint32_t(c));
    return;
  }
  if (k_ >= 32) return;  // only corr_min has 32 bits; the decoder knows it from k
  std::int64_t offset = c;
  if (offset < 0) {
    offset += (std::int64_t(1) << k_) - 1;
  } else {
    offset -= 1;
  }
  SymbolModel& model = models_.correctorModel(k_);
  if (k_ <= models_.bits_high) {
    enc.encodeSymbol(model, std::uint32_t(offset));
  } else {
    const std::uint32_t low_bits = k_ - models_.bits_high;
    const std::uint32_t low = std::uint32_t(offset) & ((1u << low_bits) - 1);
    enc.encodeSymbol(model, std::uint32_t(offset >> low_bits));
    enc.writeBits(low_bits, low);
  }
}

void IntegerEncoder::encode(ArithmeticEncoder& enc, std::int32_t prediction, std::int32_t real,
                            std::uint32_t context) {
  std::int32_t c;
  if (models_.corr_range == 0) {
    c = std::int32_t(std::uint32_t(real) - std::uint32_t(prediction));  // modulo 2^32
  } else {
    std::int64_t d = std::int64_t(real) - prediction;
    if (d < models_.corr_min) {
      d += models_.corr_range;
    } else if (d > models_.corr_max) {
      d -= models_.corr_range;
    }
    c = std::int32_t(d);
  }
  writeCorrector(enc, c, models_.kModel(context));
}

}  // namespace parallax::laz
