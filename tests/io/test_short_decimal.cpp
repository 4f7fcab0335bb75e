// The short-number fast paths (io/short_decimal.h) against the C library: every number they take
// must give the same bits as strtod (doubles) and strtof (floats), and end where strtod ends;
// what they decline must be a shape the contract says they may decline.
#include "io/short_decimal.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

namespace parallax::decimal {
namespace {

using Scanner = const char* (*)(const char*, ShortDecimal&);

struct NamedScanner {
  const char* name;
  Scanner scan;
  int max_digits;  // the most digits it must take (when the mantissa fits 2^53)
};

std::vector<NamedScanner> scanners() {
  std::vector<NamedScanner> all = {{"swar", scanShortDecimalSwar, 15}};
#if defined(PARALLAX_SHORT_DECIMAL_SSE2)
  all.push_back({"sse2", scanShortDecimalSse2, 0});  // it may decline past 16 bytes
#endif
  all.push_back({"default", scanShortDecimal, 0});
  return all;
}

// `text` followed by a blank and padding, so that the read-ahead stays inside the buffer.
std::string padded(const std::string& text) {
  return text + " " + std::string(std::size_t(kShortNumberReadAhead) + 16, ' ');
}

// What one scanner made of `text` (taken false: it declined).
struct Parsed {
  bool taken = false;
  std::size_t length = 0;
  double value = 0.0;
  bool float_taken = false;
  float narrow = 0.0f;
};

Parsed parse(Scanner scan, const std::string& text) {
  const std::string buffer = padded(text);
  ShortDecimal number;
  Parsed parsed;
  const char* stop = scan(buffer.data(), number);
  if (stop == nullptr) return parsed;
  parsed.taken = true;
  parsed.length = std::size_t(stop - buffer.data());
  parsed.value = exactDouble(number);
  parsed.float_taken = nearestFloat(number, parsed.narrow);
  return parsed;
}

// The scanner's result, where it took the text, is the C library's, bit for bit.
void expectLikeStrtod(const NamedScanner& scanner, const std::string& text) {
  SCOPED_TRACE(std::string(scanner.name) + " \"" + text + "\"");
  const Parsed parsed = parse(scanner.scan, text);
  if (!parsed.taken) return;
  const std::string buffer = padded(text);
  char* end = nullptr;
  const double expected = std::strtod(buffer.c_str(), &end);
  EXPECT_EQ(parsed.length, std::size_t(end - buffer.c_str()));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(parsed.value), std::bit_cast<std::uint64_t>(expected))
      << parsed.value << " vs " << expected;
  if (parsed.float_taken) {
    const float expected_float = std::strtof(buffer.c_str(), nullptr);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(parsed.narrow),
              std::bit_cast<std::uint32_t>(expected_float))
        << parsed.narrow << " vs " << expected_float;
  }
}

TEST(ShortDecimal, TakesTheCommonShapesExactly) {
  const char* texts[] = {"0",
                         "-0",
                         "0.0",
                         "-0.0",
                         "1",
                         "-1",
                         "9",
                         "10",
                         ".5",
                         "-.5",
                         "5.",
                         "-5.",
                         "0.1",
                         "0.2",
                         "0.3",
                         "-0.7",
                         "3.14159",
                         "0.80130386",
                         "5.3736343",
                         "-1.5534592",
                         "0.015092595",
                         "-0.0069543384",
                         "0.99918121",
                         "512000.125",
                         "4100000.5",
                         "123456789012345",
                         "0.0000000000001",
                         "000000000.5",
                         "16777217",
                         "16777219",
                         "8388609.5",
                         "999999999999999",
                         "1.000000000001"};
  for (const NamedScanner& scanner : scanners()) {
    for (const char* text : texts) {
      SCOPED_TRACE(std::string(scanner.name) + " \"" + text + "\"");
      EXPECT_TRUE(parse(scanner.scan, text).taken);
      expectLikeStrtod(scanner, text);
    }
  }
}

TEST(ShortDecimal, NegativeZeroKeepsItsSign) {
  for (const NamedScanner& scanner : scanners()) {
    SCOPED_TRACE(scanner.name);
    const Parsed parsed = parse(scanner.scan, "-0.000");
    ASSERT_TRUE(parsed.taken);
    EXPECT_TRUE(std::signbit(parsed.value));
    ASSERT_TRUE(parsed.float_taken);
    EXPECT_TRUE(std::signbit(parsed.narrow));
  }
}

TEST(ShortDecimal, DeclinesWhatTheGeneralParserMustDecide) {
  // Exponents stop before the 'e' (the caller sees no delimiter there and declines the line);
  // the rest is declined outright.
  const char* declined[] = {"",
                            "-",
                            ".",
                            "-.",
                            "+1",
                            "+.5",
                            "inf",
                            "nan",
                            "-inf",
                            "e5",
                            "--1",
                            "x",
                            "12345678901234567890",
                            "0.12345678901234567",
                            "1234567890123456.5"};
  for (const NamedScanner& scanner : scanners()) {
    for (const char* text : declined) {
      SCOPED_TRACE(std::string(scanner.name) + " \"" + text + "\"");
      EXPECT_FALSE(parse(scanner.scan, text).taken);
    }
    for (const char* text : {"1e5", "1.5e-3", "2E10", "1e400", "1e-40"}) {
      SCOPED_TRACE(std::string(scanner.name) + " \"" + text + "\"");
      const Parsed parsed = parse(scanner.scan, text);
      ASSERT_TRUE(parsed.taken);  // the mantissa only: the caller finds 'e' after it
      EXPECT_EQ(padded(text)[parsed.length],
                std::string(text).find('e') != std::string::npos ? 'e' : 'E');
    }
  }
}

TEST(ShortDecimal, LongMantissasAreTakenOnlyWhenExact) {
  // 16 to 19 digits: the SWAR scanner takes them while the mantissa is at most 2^53, and must
  // then be exact; the SSE2 one declines them.
  const char* texts[] = {"900719925474099.2", "900719925474099.3",  "0.900719925474099",
                         "1234567890.123456", "000000000000001",    "0.000000000000001",
                         "1.00000000000001",  "-0.000000000000001", "99999999999999.99"};
  for (const NamedScanner& scanner : scanners()) {
    for (const char* text : texts) expectLikeStrtod(scanner, text);
  }
  EXPECT_TRUE(parse(scanShortDecimalSwar, "900719925474099.2").taken);   // 2^53
  EXPECT_FALSE(parse(scanShortDecimalSwar, "900719925474099.3").taken);  // 2^53 + 1
  EXPECT_TRUE(parse(scanShortDecimalSwar, "0.000000000000001").taken);
  EXPECT_FALSE(parse(scanShortDecimalSwar, "0.0000000000000001").taken);  // 16 after the point
}

TEST(ShortDecimal, FloatMidpointsAreDeclinedForTheGeneralParser) {
  // 16777217 = 2^24 + 1 lies exactly halfway between the floats 2^24 and 2^24 + 2: rounding the
  // double would be right here by luck (ties to even), but nearestFloat must not guess.
  for (const NamedScanner& scanner : scanners()) {
    SCOPED_TRACE(scanner.name);
    for (const char* text : {"16777217", "16777219", "-16777217", "8388608.5"}) {
      const Parsed parsed = parse(scanner.scan, text);
      ASSERT_TRUE(parsed.taken) << text;
      EXPECT_FALSE(parsed.float_taken) << text;
    }
    // Just off the midpoint, within the margin: declined too, and never wrong when taken.
    expectLikeStrtod(scanner, "16777217.00001");
    expectLikeStrtod(scanner, "16777216.99999");
  }
}

TEST(ShortDecimal, RandomNumbersMatchTheCLibrary) {
  std::mt19937_64 random(20261122);
  std::uniform_int_distribution<int> length(0, 9), fraction_length(0, 12), digit(0, 9), coin(0, 3);
  const std::vector<NamedScanner> all = scanners();
  for (int n = 0; n < 40000; ++n) {
    std::string text = coin(random) == 0 ? "-" : "";
    const int integer_digits = length(random), fraction_digits = fraction_length(random);
    for (int k = 0; k < integer_digits; ++k) text += char('0' + digit(random));
    if (fraction_digits > 0 || coin(random) == 0) text += '.';
    for (int k = 0; k < fraction_digits; ++k) text += char('0' + digit(random));
    for (const NamedScanner& scanner : all) {
      const Parsed parsed = parse(scanner.scan, text);
      const std::size_t unsigned_length = text.size() - (text[0] == '-');
      if (integer_digits + fraction_digits > 0 && unsigned_length <= 15) {
        // Every scanner takes up to 15 digits within 15 bytes (then the delimiter).
        ASSERT_TRUE(parsed.taken) << scanner.name << " \"" << text << "\"";
      }
      if (parsed.taken && !parsed.float_taken) {
        // Declined as a float only next to a float midpoint (ties among them: integers above
        // 2^24, whose midpoints are exact).
        const std::uint64_t low = std::bit_cast<std::uint64_t>(std::strtod(text.c_str(), nullptr)) &
                                  ((std::uint64_t{1} << 29) - 1);
        const std::int64_t from_midpoint = std::int64_t(low) - (std::int64_t{1} << 28);
        EXPECT_LE(std::abs(from_midpoint), 8) << scanner.name << " \"" << text << "\"";
      }
      expectLikeStrtod(scanner, text);
      if (HasFailure()) return;
    }
  }
}

TEST(ShortDecimal, UnsignedIntegers) {
  struct Case {
    const char* text;
    bool taken;
    std::uint32_t value;
    std::size_t length;
  };
  const Case cases[] = {
      {"0", true, 0, 1},         {"7", true, 7, 1},       {"255", true, 255, 3},
      {"256", true, 256, 3},     {"007", true, 7, 3},     {"1234567", true, 1234567, 7},
      {"12345678", false, 0, 0}, {"-1", false, 0, 0},     {"+1", false, 0, 0},
      {"", false, 0, 0},         {"255.0", true, 255, 3}, {"1e2", true, 1, 1}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const std::string buffer = padded(c.text);
    std::uint32_t value = 0;
    const char* stop = parseShortUnsigned(buffer.data(), value);
    ASSERT_EQ(stop != nullptr, c.taken);
    if (!c.taken) continue;
    EXPECT_EQ(value, c.value);
    EXPECT_EQ(std::size_t(stop - buffer.data()), c.length);
  }
}

}  // namespace
}  // namespace parallax::decimal
