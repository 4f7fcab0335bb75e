// LASzip's arithmetic encoder: the exact inverse of ArithmeticDecoder (see
// arithmetic_models.h for the source). It appends to a byte vector owned by the caller; a carry
// out of the 32-bit interval base ripples back through the bytes already written.
#pragma once

#include <cstdint>
#include <vector>

#include "io/laz/arithmetic_models.h"

namespace parallax::laz {

class ArithmeticEncoder {
 public:
  // Appends the stream to `out` (which must outlive the encoder until finish()).
  explicit ArithmeticEncoder(std::vector<std::uint8_t>& out) : out_(&out), first_(out.size()) {}

  void encodeBit(BitModel& m, std::uint32_t bit) {
    const std::uint32_t x = m.bit0_prob * (length_ >> kBitLengthShift);
    if (bit == 0) {
      length_ = x;
      ++m.bit0_count;
    } else {
      addToBase(x);
      length_ -= x;
    }
    if (length_ < kMinLength) renormalize();
    if (--m.bits_until_update == 0) m.update();
  }

  void encodeSymbol(SymbolModel& m, std::uint32_t symbol) {
    const std::uint32_t* dist = m.distribution.data();
    if (symbol == m.lastSymbol()) {
      const std::uint32_t x = dist[symbol] * (length_ >> kSymbolLengthShift);
      addToBase(x);
      length_ -= x;
    } else {
      const std::uint32_t x = dist[symbol] * (length_ >>= kSymbolLengthShift);
      addToBase(x);
      length_ = dist[symbol + 1] * length_ - x;
    }
    if (length_ < kMinLength) renormalize();
    ++m.counts[symbol];
    if (--m.symbols_until_update == 0) m.update();
  }

  // Raw bits (1..32; `value` below 2^bits); more than 19 go as 16 low bits, then the rest.
  void writeBits(std::uint32_t bits, std::uint32_t value) {
    if (bits > 19) {
      writeShort(std::uint16_t(value & 0xFFFF));
      value >>= 16;
      bits -= 16;
    }
    writeRaw(bits, value);
  }
  void writeBit(std::uint32_t bit) { writeRaw(1, bit); }
  void writeByte(std::uint8_t value) { writeRaw(8, value); }
  void writeShort(std::uint16_t value) { writeRaw(16, value); }
  void writeInt(std::uint32_t value) {
    writeShort(std::uint16_t(value & 0xFFFF));
    writeShort(std::uint16_t(value >> 16));
  }
  void writeInt64(std::uint64_t value) {
    writeInt(std::uint32_t(value));
    writeInt(std::uint32_t(value >> 32));
  }

  // Ends the stream: the final bytes that pin the code value inside the interval, padded so
  // that the decoder's four-byte look-ahead stays inside the stream. Returns the bytes this
  // encoder appended. The encoder must not be used afterwards.
  std::size_t finish();

 private:
  void addToBase(std::uint32_t x) {
    const std::uint32_t before = base_;
    base_ += x;
    if (base_ < before) propagateCarry();
  }
  void writeRaw(std::uint32_t bits, std::uint32_t value) {
    addToBase(value * (length_ >>= bits));
    if (length_ < kMinLength) renormalize();
  }
  void renormalize() {
    do {
      out_->push_back(std::uint8_t(base_ >> 24));
      base_ <<= 8;
    } while ((length_ <<= 8) < kMinLength);
  }
  void propagateCarry();

  std::vector<std::uint8_t>* out_;
  std::size_t first_;  // where this stream starts in *out_
  std::uint32_t base_ = 0;
  std::uint32_t length_ = kMaxLength;
};

}  // namespace parallax::laz
