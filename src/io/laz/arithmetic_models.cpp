#include "io/laz/arithmetic_models.h"

#include <cassert>

namespace parallax::laz {

void BitModel::update() {
  // Halve the counts when their total passes 2^13, keeping P(0) below 1.
  if ((bit_count += update_cycle) > kBitMaxCount) {
    bit_count = (bit_count + 1) >> 1;
    bit0_count = (bit0_count + 1) >> 1;
    if (bit0_count == bit_count) ++bit_count;
  }
  // P(0) = bit0_count / bit_count in 13 bits, through a 31-bit reciprocal as FastAC rounds it.
  const std::uint32_t scale = 0x80000000u / bit_count;
  bit0_prob = (bit0_count * scale) >> (31 - kBitLengthShift);
  update_cycle = (5 * update_cycle) >> 2;
  if (update_cycle > 64) update_cycle = 64;
  bits_until_update = update_cycle;
}

SymbolModel::SymbolModel(std::uint32_t symbols, bool for_decoding) : symbols_(symbols) {
  assert(symbols >= 2 && symbols <= kMaxSymbols && "SymbolModel needs 2..2048 symbols");
  distribution.resize(symbols);
  counts.resize(symbols);
  if (for_decoding && symbols > 16) {
    // LASzip's decoder sizes its table at about a quarter of the symbols (16 entries for the
    // corrector-size models of 33 symbols), so a lookup leaves about four candidates and a
    // bisection of two or three unpredictable branches: the hottest loop of a decode (half its
    // time in a profile). Up to eight entries a symbol leave a single candidate for most
    // values: only a value whose entry holds a symbol boundary needs the search, and the result
    // is the same (the table only narrows where the search starts). At most 256 entries: the
    // scaled value value / (length >> 15) can pass 2^15 by up to 63 (length >= 2^24), which the
    // two entries past the table cover only for a shift of 7 bits or more.
    std::uint32_t table_bits = 3;
    while ((1u << table_bits) < 8 * symbols && table_bits < 8) ++table_bits;
    table_size = 1u << table_bits;
    table_shift = kSymbolLengthShift - table_bits;
    table.resize(table_size + 2);
  }
  reset();
}

void SymbolModel::reset() {
  total_count_ = 0;
  update_cycle_ = symbols_;
  for (std::uint32_t& count : counts) count = 1;
  update();
  symbols_until_update = update_cycle_ = (symbols_ + 6) >> 1;
}

void SymbolModel::update() {
  if ((total_count_ += update_cycle_) > kSymbolMaxCount) {
    total_count_ = 0;
    for (std::uint32_t& count : counts) total_count_ += (count = (count + 1) >> 1);
  }
  const std::uint32_t scale = 0x80000000u / total_count_;
  std::uint32_t sum = 0;
  if (table.empty()) {
    for (std::uint32_t k = 0; k < symbols_; ++k) {
      distribution[k] = (scale * sum) >> (31 - kSymbolLengthShift);
      sum += counts[k];
    }
  } else {
    // table[t] = the last symbol whose distribution is at most t << table_shift, so a search
    // for a scaled value v starts at table[v >> shift] and ends before table[(v >> shift) + 1].
    std::uint32_t s = 0;
    for (std::uint32_t k = 0; k < symbols_; ++k) {
      distribution[k] = (scale * sum) >> (31 - kSymbolLengthShift);
      sum += counts[k];
      const std::uint32_t w = distribution[k] >> table_shift;
      while (s < w) table[++s] = std::uint16_t(k - 1);
    }
    table[0] = 0;
    while (s <= table_size) table[++s] = std::uint16_t(symbols_ - 1);
  }
  update_cycle_ = (5 * update_cycle_) >> 2;
  const std::uint32_t max_cycle = (symbols_ + 6) << 3;
  if (update_cycle_ > max_cycle) update_cycle_ = max_cycle;
  symbols_until_update = update_cycle_;
}

}  // namespace parallax::laz
