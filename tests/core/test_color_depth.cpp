#include "core/color_depth.h"

#include <gtest/gtest.h>

#include <cmath>

namespace parallax {
namespace {

// Every 8-bit value survives 8 -> 16 -> 8, and 16 -> 8 is the nearest of v * 255 / 65535
// (computed here in double: no tie exists, since v * 255 / 65535 = v / 257 never ends in .5).
TEST(ColorDepth, EightBitsRoundTripAndSixteenBitsRoundToTheNearest) {
  for (unsigned c = 0; c < 256; ++c) {
    EXPECT_EQ(colorTo16Bits(std::uint8_t(c)), (c << 8) | c) << c;
    EXPECT_EQ(colorTo8Bits(colorTo16Bits(std::uint8_t(c))), c) << c;
  }
  for (unsigned v = 0; v < 65536; ++v) {
    const auto nearest = unsigned(std::lround(double(v) * 255.0 / 65535.0));
    ASSERT_EQ(colorTo8Bits(std::uint16_t(v)), nearest) << v;
  }
}

TEST(ColorDepth, AnUnscaledFileKeepsItsValuesBothWays) {
  EXPECT_EQ(shownColor(200, true), 200);
  EXPECT_EQ(shownColor(200, false), 1);  // 200 / 257 rounds to 1
  EXPECT_EQ(storedColor(200, true), 200);
  EXPECT_EQ(storedColor(200, false), 51400);
}

}  // namespace
}  // namespace parallax
