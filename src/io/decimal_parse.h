// Internal to the ascii readers (PLY ascii bodies, text files): the decimal numbers point files
// are made of, parsed fast and exactly. Anything these functions decline (they return nullptr)
// goes to fast_float.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace parallax::decimal {

// Powers of ten exactly representable as doubles.
constexpr double kPowersOfTen[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                   1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                   1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// The common shape of numbers in point files, [+-]digits[.digits] with at most 15 significant
// digits, parsed directly: the mantissa is an exact integer below 2^53 and 10^k is exact, so one
// IEEE division gives the correctly rounded double (Clinger's fast path). Returns nullptr for
// anything else (exponents, long mantissas, inf, nan), which goes to fast_float. This is the
// byte-by-byte form, for the last bytes of a file; parseSimpleDecimal below is the fast one.
inline const char* parseSimpleDecimalScalar(const char* p, const char* end, double& out,
                                            int& fraction) {
  bool negative = false;
  if (p != end && (*p == '-' || *p == '+')) negative = *p++ == '-';
  std::uint64_t mantissa = 0;
  int digits = 0;
  fraction = 0;
  while (p != end && unsigned(*p - '0') < 10) {
    mantissa = mantissa * 10 + unsigned(*p++ - '0');
    ++digits;
  }
  if (p != end && *p == '.') {
    ++p;
    while (p != end && unsigned(*p - '0') < 10) {
      mantissa = mantissa * 10 + unsigned(*p++ - '0');
      ++digits, ++fraction;
    }
  }
  if (digits == 0 || digits > 15 || (p != end && (*p == 'e' || *p == 'E'))) return nullptr;
  double value = double(mantissa);
  if (fraction > 0) value /= kPowersOfTen[fraction];
  out = negative ? -value : value;
  return p;
}

// SWAR digit runs: 8 bytes loaded at once, the run of leading digits found with bit tricks and
// converted with three multiplies. Digit-by-digit loops mispredict at every run's end (numbers
// in point files vary in length), which costs more than the arithmetic.
inline int leadingDigits(std::uint64_t chunk) {
  constexpr std::uint64_t kHigh = 0x8080808080808080ull;
  std::uint64_t above_nine = chunk + 0x4646464646464646ull;               // high bit: byte > '9'
  std::uint64_t at_least_zero = (chunk | kHigh) - 0x3030303030303030ull;  // high bit: byte >= '0'
  // Carries and borrows only move towards later bytes, past the first non-digit: harmless.
  std::uint64_t non_digit = (above_nine | ~at_least_zero | chunk) & kHigh;
  return non_digit == 0 ? 8 : std::countr_zero(non_digit) >> 3;
}

// The value of the first `count` (1 to 8) digit bytes of `chunk` (first byte lowest).
inline std::uint64_t digitsValue(std::uint64_t chunk, int count) {
  std::uint64_t v = (chunk - 0x3030303030303030ull) << (8 * (8 - count));
  v = v * 10 + (v >> 8);
  return (((v & 0x000000FF000000FFull) * (100 + (1000000ull << 32))) +
          (((v >> 16) & 0x000000FF000000FFull) * (1 + (10000ull << 32)))) >>
         32;
}

constexpr std::uint64_t kIntegerPowersOfTen[] = {1,      10,      100,      1000,     10000,
                                                 100000, 1000000, 10000000, 100000000};

// Appends the run of digits at `p` to `mantissa`; false if the run reaches too near the end.
inline bool digitRun(const char*& p, const char* end, std::uint64_t& mantissa, int& digits) {
  for (;;) {
    if (end - p < 8) return false;
    std::uint64_t chunk;
    std::memcpy(&chunk, p, 8);
    int n = leadingDigits(chunk);
    if (n > 0) {
      mantissa = mantissa * kIntegerPowersOfTen[n] + digitsValue(chunk, n);
      p += n;
      digits += n;
    }
    if (n < 8) return true;
  }
}

// parseSimpleDecimalScalar's contract, a run of digits at a time. `fraction` is the number of
// digits after the decimal point (0 without one).
inline const char* parseSimpleDecimal(const char* p, const char* end, double& out, int& fraction) {
  const char* start = p;
  bool negative = false;
  if (p != end && (*p == '-' || *p == '+')) negative = *p++ == '-';
  std::uint64_t mantissa = 0;
  int digits = 0;
  fraction = 0;
  if (!digitRun(p, end, mantissa, digits))
    return parseSimpleDecimalScalar(start, end, out, fraction);
  if (*p == '.') {
    ++p;
    int integer_digits = digits;
    if (!digitRun(p, end, mantissa, digits)) {
      return parseSimpleDecimalScalar(start, end, out, fraction);
    }
    fraction = digits - integer_digits;
  }
  if (digits == 0 || digits > 15 || *p == 'e' || *p == 'E') return nullptr;
  double value = double(mantissa);
  if (fraction > 0) value /= kPowersOfTen[fraction];
  out = negative ? -value : value;
  return p;
}

// The parts of a number "[+-]digits[.digits]" of at most 15 significant digits, without making
// a double of it: value = (negative ? -1 : 1) * mantissa / 10^fraction. The text readers store
// positions with a decimal scale as integers from these parts (no division, no rounding). Returns
// nullptr for anything else, or when fewer than 8 bytes follow the number (callers then take
// the double path).
inline const char* parseDecimalParts(const char* p, const char* end, std::uint64_t& mantissa,
                                     bool& negative, int& fraction) {
  negative = false;
  if (p != end && (*p == '-' || *p == '+')) negative = *p++ == '-';
  mantissa = 0;
  int digits = 0;
  fraction = 0;
  if (!digitRun(p, end, mantissa, digits)) return nullptr;
  if (*p == '.') {
    ++p;
    const int integer_digits = digits;
    if (!digitRun(p, end, mantissa, digits)) return nullptr;
    fraction = digits - integer_digits;
  }
  if (digits == 0 || digits > 15 || *p == 'e' || *p == 'E') return nullptr;
  return p;
}

// True when float(d) is the float nearest to every real within half a double ulp of d: d is a
// normal float-range value whose 29 bits below float precision are not within one of the
// midpoint pattern. Then the correctly rounded double of a decimal rounds to its correct float.
inline bool roundsSafelyToFloat(double d) {
  double magnitude = std::abs(d);
  if (magnitude == 0.0) return true;
  if (!(magnitude >= 0x1p-126 && magnitude <= 0x1.fffffep127)) return false;
  std::uint64_t low = std::bit_cast<std::uint64_t>(d) & ((std::uint64_t{1} << 29) - 1);
  constexpr std::uint64_t kHalf = std::uint64_t{1} << 28;
  return low + 1 < kHalf || low > kHalf + 1;
}

}  // namespace parallax::decimal
