// The adaptive probability models of LASzip's arithmetic coder: a binary model and a model of
// an alphabet of 2..2048 symbols. Both re-estimate their probabilities only every few symbols
// ("periodic updates"), at a rate that slows down as they learn.
//
// Source: A. Said, "Introduction to Arithmetic Coding - Theory and Practice", HP Labs report
// HPL-2004-76 (the FastAC design: 32-bit interval, 13-bit bit probabilities, 15-bit symbol
// distributions), as adapted by M. Isenburg for LASzip ("LASzip: lossless compression of LiDAR
// data", PE&RS 79(2), 2013). A LAZ file decodes correctly only when the models update at exactly
// the same moments and round exactly as the writer's did, so every constant and every rounding
// step below is part of the format, not a tuning choice.
#pragma once

#include <cstdint>
#include <vector>

namespace parallax::laz {

// Renormalise when the interval length falls below 2^24 (one byte can be shifted out).
inline constexpr std::uint32_t kMinLength = 0x01000000u;
inline constexpr std::uint32_t kMaxLength = 0xFFFFFFFFu;
// Bit models: probabilities of 13 bits; counts halved above 2^13.
inline constexpr std::uint32_t kBitLengthShift = 13;
inline constexpr std::uint32_t kBitMaxCount = 1u << kBitLengthShift;
// Symbol models: distributions of 15 bits; counts halved above 2^15.
inline constexpr std::uint32_t kSymbolLengthShift = 15;
inline constexpr std::uint32_t kSymbolMaxCount = 1u << kSymbolLengthShift;
inline constexpr std::uint32_t kMaxSymbols = 1u << 11;

// An adaptive model of one bit. Starts equiprobable, updates after 4 bits, then every 5/4 as
// many bits as the last time, up to every 64 bits.
struct BitModel {
  std::uint32_t bit0_count = 1;
  std::uint32_t bit_count = 2;
  std::uint32_t bit0_prob = 1u << (kBitLengthShift - 1);  // P(0) in 1/2^13
  std::uint32_t update_cycle = 4;
  std::uint32_t bits_until_update = 4;

  void reset() { *this = BitModel{}; }
  // Re-estimates bit0_prob from the counts (called by the coders every bits_until_update bits).
  void update();
};

// An adaptive model of `symbols` symbols (2..2048). The cumulative distribution is scaled to
// 2^15; a decoder of more than 16 symbols also keeps a table from the top bits of a scaled value
// to a symbol range (about eight entries a symbol, finer than LASzip's), which only speeds up its
// search (the result is the same without it).
class SymbolModel {
 public:
  // `for_decoding` builds the lookup table (decoders of more than 16 symbols).
  SymbolModel(std::uint32_t symbols, bool for_decoding);

  // Back to equiprobable counts (the state at the start of every chunk).
  void reset();
  // Halves the counts when they exceed 2^15, recomputes the distribution and the table, and
  // sets when the next update happens.
  void update();

  std::uint32_t symbols() const { return symbols_; }
  std::uint32_t lastSymbol() const { return symbols_ - 1; }

  // The coders work on these directly (hot path).
  std::vector<std::uint32_t> distribution;  // symbols entries, distribution[0] == 0
  std::vector<std::uint32_t> counts;        // symbols entries
  std::vector<std::uint16_t> table;         // table_size + 2 entries, empty without a table
  std::uint32_t table_shift = 0;
  std::uint32_t table_size = 0;
  std::uint32_t symbols_until_update = 0;

 private:
  std::uint32_t symbols_;
  std::uint32_t total_count_ = 0;
  std::uint32_t update_cycle_ = 0;
};

}  // namespace parallax::laz
