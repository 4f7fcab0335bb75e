// Internal to the ascii readers: the fast paths for the short numbers of point files,
// "[-]digits[.digits]" with few digits, parsed without bounds checks and with few branches.
//
// Contract of every function here: the caller guarantees kShortNumberReadAhead readable bytes
// from the number's first byte, and checks what follows the number (a blank or the line end,
// else it is not a number of theirs). They return nullptr for anything they do not take whole
// ('+', exponents, long mantissas, inf, nan, garbage), and the general parsers (decimal_parse.h,
// then fast_float) decide. What they return is exact: the same bits as strtod / strtof.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "io/decimal_parse.h"

#if defined(__SSE2__) && defined(__x86_64__)
#include <emmintrin.h>
#define PARALLAX_SHORT_DECIMAL_SSE2 1
#endif

namespace parallax::decimal {

constexpr std::ptrdiff_t kShortNumberReadAhead = 40;

constexpr std::uint64_t kIntegerPowersOfTen16[] = {1ull,
                                                   10ull,
                                                   100ull,
                                                   1000ull,
                                                   10000ull,
                                                   100000ull,
                                                   1000000ull,
                                                   10000000ull,
                                                   100000000ull,
                                                   1000000000ull,
                                                   10000000000ull,
                                                   100000000000ull,
                                                   1000000000000ull,
                                                   10000000000000ull,
                                                   100000000000000ull,
                                                   1000000000000000ull,
                                                   10000000000000000ull};

// A short decimal as read: the value is (negative ? -1 : 1) * mantissa / 10^power, with
// mantissa <= 2^53 and power <= 15, so both are exact doubles.
struct ShortDecimal {
  std::uint64_t mantissa = 0;
  int power = 0;
  bool negative = false;
};

inline std::uint64_t load8(const char* p) {
  std::uint64_t chunk;
  std::memcpy(&chunk, p, 8);
  return chunk;
}

// digitsValue for 0 to 8 digits: the shift is split in two so that 0 digits (a shift by 64,
// undefined in one step) gives 0 without a branch.
inline std::uint64_t digitsValueOrZero(std::uint64_t chunk, int count) {
  const int half_shift = 4 * (8 - count);
  std::uint64_t v = ((chunk - 0x3030303030303030ull) << half_shift) << half_shift;
  v = v * 10 + (v >> 8);
  return (((v & 0x000000FF000000FFull) * (100 + (1000000ull << 32))) +
          (((v >> 16) & 0x000000FF000000FFull) * (1 + (10000ull << 32)))) >>
         32;
}

// The run of at most 16 digits at `p` (16 bytes are read): its length (16: it may go on) and
// value. Branch-free: the lengths of numbers vary from one to the next, so branches on them
// mispredict.
inline int digitRun16(const char* p, std::uint64_t& value) {
  const std::uint64_t first = load8(p), second = load8(p + 8);
  const int n = leadingDigits(first);
  const int m = n == 8 ? leadingDigits(second) : 0;
  value = digitsValueOrZero(first, n) * kIntegerPowersOfTen[m] + digitsValueOrZero(second, m);
  return n + m;
}

// Portable (SWAR, 8 bytes at a time): at most 19 digits in all (leading zeros included), at most
// 15 after the point, a mantissa of at most 2^53. scanShortDecimal below is the one to call.
inline const char* scanShortDecimalSwar(const char* p, ShortDecimal& out) {
  out.negative = *p == '-';
  p += out.negative;
  std::uint64_t integer = 0, fraction = 0;
  const int integer_digits = digitRun16(p, integer);
  p += integer_digits;
  const bool has_point = *p == '.';
  p += has_point;
  // Read even without a point (a harmless load), then dropped: no branch on the shape.
  int fraction_digits = digitRun16(p, fraction);
  fraction_digits = has_point ? fraction_digits : 0;
  fraction = has_point ? fraction : 0;
  p += fraction_digits;
  const int digits = integer_digits + fraction_digits;
  // A run of 16 may go on past what was read; 19 digits cannot overflow 64 bits.
  if (digits == 0 || digits > 19 || integer_digits == 16 || fraction_digits > 15) return nullptr;
  out.mantissa = integer * kIntegerPowersOfTen16[fraction_digits] + fraction;
  out.power = fraction_digits;
  if (out.mantissa > (std::uint64_t{1} << 53)) return nullptr;
  return p;
}

#if defined(PARALLAX_SHORT_DECIMAL_SSE2)
// Bytes [0, n) of a 16-byte mask: loaded from kLeadingOnes + 16 - n (n = 0 to 16).
alignas(16) constexpr unsigned char kLeadingOnes[32] = {
    0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};

inline __m128i leadingBytes(int n) {
  return _mm_loadu_si128(reinterpret_cast<const __m128i*>(kLeadingOnes + 16 - n));
}

// At most 15 digits, the number (point included) and the byte after it within the 16 bytes
// read, in one SSE2 register: digits and point found by one compare, the point squeezed out by
// moving the integer digits one byte up, and the 16 bytes (a zero, the digits D, zeros) converted
// as one 16-digit integer V by multiply-adds (pairs, quads, octets). V = D * 10^(15 - digits), so
// D / 10^fraction_digits = V / 10^(15 - integer_digits), and V < 10^15.
inline const char* scanShortDecimalSse2(const char* p, ShortDecimal& out) {
  out.negative = *p == '-';
  p += out.negative;
  const __m128i raw = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
  const __m128i values = _mm_xor_si128(raw, _mm_set1_epi8('0'));  // '0'..'9' -> 0..9
  const __m128i is_digit = _mm_cmpeq_epi8(_mm_min_epu8(values, _mm_set1_epi8(9)), values);
  const unsigned stops = ~unsigned(_mm_movemask_epi8(is_digit));  // bits 16 and up set
  const unsigned points = unsigned(_mm_movemask_epi8(_mm_cmpeq_epi8(raw, _mm_set1_epi8('.'))));
  // The point, when it is the first non-digit; the number ends at the next non-digit. (From the
  // masks, not a load of the byte: shorter dependency chains. `stops` is never 0: __builtin_ctz
  // needs no zero check.)
  const unsigned point = stops & (0u - stops) & points;
  const int integer_digits = __builtin_ctz(stops);
  const int end = __builtin_ctz(stops ^ point);
  const bool has_point = point != 0;
  if (end == int(has_point) || end > 15) return nullptr;  // no digits, or it may go on
  const __m128i digit_values = _mm_and_si128(values, is_digit);
  const __m128i integer_mask = leadingBytes(integer_digits);
  const __m128i integer_part = _mm_slli_si128(_mm_and_si128(digit_values, integer_mask), 1);
  const __m128i fraction_part =
      _mm_andnot_si128(integer_mask, _mm_and_si128(digit_values, leadingBytes(end)));
  const __m128i d = _mm_or_si128(integer_part, fraction_part);  // byte 0 most significant
  const __m128i pairs =
      _mm_add_epi16(_mm_mullo_epi16(_mm_and_si128(d, _mm_set1_epi16(0xFF)), _mm_set1_epi16(10)),
                    _mm_srli_epi16(d, 8));
  const __m128i quads = _mm_madd_epi16(pairs, _mm_set1_epi32(100 | (1 << 16)));
  const __m128i packed = _mm_packs_epi32(quads, quads);  // each < 10^4: no saturation
  const __m128i octets = _mm_madd_epi16(packed, _mm_set1_epi32(10000 | (1 << 16)));
  const std::uint64_t both = std::uint64_t(_mm_cvtsi128_si64(octets));
  out.mantissa = (both & 0xFFFFFFFFu) * 100000000u + (both >> 32);
  out.power = 15 - integer_digits;
  return p + end;
}
#endif

// The scanner of this machine: SSE2 on x86-64 (it declines numbers over 15 digits), else SWAR.
inline const char* scanShortDecimal(const char* p, ShortDecimal& out) {
#if defined(PARALLAX_SHORT_DECIMAL_SSE2)
  return scanShortDecimalSse2(p, out);
#else
  return scanShortDecimalSwar(p, out);
#endif
}

// `magnitude` with the sign of `negative`, without a branch (signs vary from value to value).
inline double withSign(double magnitude, bool negative) {
  return std::bit_cast<double>(std::bit_cast<std::uint64_t>(magnitude) |
                               (std::uint64_t(negative) << 63));
}

// The correctly rounded double: both operands exact, one IEEE division (Clinger's fast path).
inline double exactDouble(const ShortDecimal& d) {
  return withSign(double(d.mantissa) / kPowersOfTen[d.power], d.negative);
}

// The doubles nearest to 10^-k.
constexpr double kNegativePowersOfTen[] = {1e0,  1e-1, 1e-2,  1e-3,  1e-4,  1e-5,  1e-6,  1e-7,
                                           1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15};

// The float nearest to the decimal, without a division (a divider is slow, and one per value
// was the bottleneck): the product of the exact mantissa and the double nearest to 10^-power
// is within 2^-52 relative of the true value (two roundings of 2^-53), so within 2 ulps of the
// double. Rounding that double to float gives the float nearest to the true value unless a float
// midpoint (29 low bits 0x10000000 in a double of float range) lies within those 2 ulps; then
// (about 9 values in 2^29) false, and the caller parses the text as a float. The values are
// 0 or 10^-15 to 2^53: float's normal range, no overflow.
inline bool nearestFloat(const ShortDecimal& d, float& out) {
  const double approximate = double(d.mantissa) * kNegativePowersOfTen[d.power];
  const std::uint64_t low = std::bit_cast<std::uint64_t>(approximate) & ((1u << 29) - 1);
  constexpr std::uint64_t kMidpoint = std::uint64_t{1} << 28, kMargin = 4;
  if (low - (kMidpoint - kMargin) <= 2 * kMargin) return false;  // unsigned: |low - mid| <= 4
  out = float(withSign(approximate, d.negative));
  return true;
}

// 1 to 7 decimal digits, no sign: an unsigned integer, for integer properties. Anything else (a
// sign, "255.0" is seen by the caller's delimiter check, more digits) returns nullptr.
inline const char* parseShortUnsigned(const char* p, std::uint32_t& out) {
  const std::uint64_t chunk = load8(p);
  const int n = leadingDigits(chunk);
  if (n == 0 || n == 8) return nullptr;
  out = std::uint32_t(digitsValueOrZero(chunk, n));
  return p + n;
}

}  // namespace parallax::decimal
