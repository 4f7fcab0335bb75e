// LASzip's arithmetic decoder over one byte range (a chunk, or one layer of a layered chunk).
//
// The decoder keeps a 32-bit interval length and the code value's offset in it; each decoded
// symbol narrows the interval, and whenever its length drops below 2^24 a byte is shifted in
// (see arithmetic_models.h for the source). The encoder ends a stream with exactly as many bytes
// as the decoder will read, so a valid stream never reads past its end.
//
// Bad input never crashes or hangs the decoder: reading past the range yields zero bytes and is
// counted, an impossible value (raw bits above their range, a code value past the symbol
// table) is clamped and flagged, and every step consumes at least one decision. The caller
// checks `ok()` (per point or per chunk) and reports where the stream went wrong.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "io/laz/arithmetic_models.h"

namespace parallax::laz {

class ArithmeticDecoder {
 public:
  ArithmeticDecoder() = default;

  // Starts decoding `bytes` (the first four bytes form the initial code value). An empty range
  // is valid: LASzip's layered chunks leave unchanged layers empty, and their decoder is never
  // asked for a symbol.
  void start(std::span<const std::byte> bytes) {
    pos_ = reinterpret_cast<const std::uint8_t*>(bytes.data());
    end_ = pos_ + bytes.size();
    overrun_ = 0;
    corrupt_ = false;
    length_ = kMaxLength;
    value_ = 0;
    if (bytes.empty()) return;
    for (int i = 0; i < 4; ++i) value_ = (value_ << 8) | nextByte();
  }

  // False once the stream read past its range or decoded an impossible value.
  bool ok() const { return overrun_ == 0 && !corrupt_; }
  bool overran() const { return overrun_ != 0; }
  // Bytes of the range consumed so far (at most its size).
  std::size_t consumed(std::span<const std::byte> bytes) const {
    return std::size_t(pos_ - reinterpret_cast<const std::uint8_t*>(bytes.data()));
  }

  std::uint32_t decodeBit(BitModel& m) {
    const std::uint32_t x = m.bit0_prob * (length_ >> kBitLengthShift);
    std::uint32_t bit;
    if (value_ < x) {
      bit = 0;
      length_ = x;
      ++m.bit0_count;
    } else {
      bit = 1;
      value_ -= x;
      length_ -= x;
    }
    if (length_ < kMinLength) renormalize();
    if (--m.bits_until_update == 0) m.update();
    return bit;
  }

  std::uint32_t decodeSymbol(SymbolModel& m) {
    std::uint32_t symbol, x, y = length_;
    const std::uint32_t* dist = m.distribution.data();
    if (!m.table.empty()) {
      // The table gives a short range of candidates; bisection finishes the search.
      const std::uint32_t dv = value_ / (length_ >>= kSymbolLengthShift);
      std::uint32_t t = dv >> m.table_shift;
      if (t > m.table_size) {  // only a corrupt stream has value >= length
        t = m.table_size;
        corrupt_ = true;
      }
      symbol = m.table[t];
      std::uint32_t n = m.table[t + 1] + 1;
      while (n > symbol + 1) {
        const std::uint32_t k = (symbol + n) >> 1;
        if (dist[k] > dv) {
          n = k;
        } else {
          symbol = k;
        }
      }
      x = dist[symbol] * length_;
      if (symbol != m.lastSymbol()) y = dist[symbol + 1] * length_;
    } else {
      // Small alphabets: bisection on the products directly.
      x = symbol = 0;
      length_ >>= kSymbolLengthShift;
      std::uint32_t n = m.symbols();
      std::uint32_t k = n >> 1;
      do {
        const std::uint32_t z = length_ * dist[k];
        if (z > value_) {
          n = k;
          y = z;
        } else {
          symbol = k;
          x = z;
        }
      } while ((k = (symbol + n) >> 1) != symbol);
    }
    value_ -= x;
    length_ = y - x;
    if (length_ < kMinLength) renormalize();
    ++m.counts[symbol];
    if (--m.symbols_until_update == 0) m.update();
    return symbol;
  }

  // Raw (equiprobable) bits, 1..32 of them; more than 19 are read as 16 low bits, then the rest.
  std::uint32_t readBits(std::uint32_t bits) {
    if (bits > 19) {
      const std::uint32_t low = readShort();
      return (readBits(bits - 16) << 16) | low;
    }
    return readRaw(bits);
  }
  std::uint32_t readBit() { return readRaw(1); }
  std::uint8_t readByte() { return std::uint8_t(readRaw(8)); }
  std::uint16_t readShort() { return std::uint16_t(readRaw(16)); }
  std::uint32_t readInt() {
    const std::uint32_t low = readShort();
    return (std::uint32_t(readShort()) << 16) | low;
  }
  std::uint64_t readInt64() {
    const std::uint64_t low = readInt();
    return (std::uint64_t(readInt()) << 32) | low;
  }

 private:
  std::uint32_t readRaw(std::uint32_t bits) {
    const std::uint32_t symbol = value_ / (length_ >>= bits);
    value_ -= length_ * symbol;
    if (length_ < kMinLength) renormalize();
    if (symbol >= (1u << bits)) {
      corrupt_ = true;
      return (1u << bits) - 1;
    }
    return symbol;
  }

  std::uint8_t nextByte() {
    if (pos_ < end_) return *pos_++;
    ++overrun_;
    return 0;
  }

  void renormalize() {
    do {
      value_ = (value_ << 8) | nextByte();
    } while ((length_ <<= 8) < kMinLength);
  }

  const std::uint8_t* pos_ = nullptr;
  const std::uint8_t* end_ = nullptr;
  std::uint32_t value_ = 0;
  std::uint32_t length_ = kMaxLength;
  std::uint32_t overrun_ = 0;
  bool corrupt_ = false;
};

}  // namespace parallax::laz
