#include "core/quantization.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace parallax {
namespace {

TEST(Quantization, IdentityForEmptyBounds) {
  Quantization q = chooseQuantization(Bounds3{});
  EXPECT_EQ(q, Quantization{});
}

TEST(Quantization, ScaleIsPowerOfTwoAndOffsetIsMultipleOfIt) {
  Bounds3 b;
  b.extend(596000.25, 4200000.5, 10.0);
  b.extend(597000.75, 4201000.0, 95.5);
  Quantization q = chooseQuantization(b);
  for (int axis = 0; axis < 3; ++axis) {
    int exponent = 0;
    EXPECT_EQ(std::frexp(q.scale[axis], &exponent), 0.5) << "axis " << axis;
    EXPECT_EQ(std::fmod(q.offset[axis], q.scale[axis]), 0.0) << "axis " << axis;
    EXPECT_TRUE(q.fits(axis, b.min[axis]));
    EXPECT_TRUE(q.fits(axis, b.max[axis]));
  }
}

TEST(Quantization, UtmDoublesOnABinaryGridRoundTripExactly) {
  Bounds3 b;
  b.extend(596232.0, 4200000.0, 0.0);
  b.extend(597232.0, 4201000.0, 100.0);
  Quantization q = chooseQuantization(b);
  for (double x : {596732.4375, 596232.0, 597231.9990234375}) {
    EXPECT_EQ(q.toWorld(0, q.toQuantized(0, x)), x);
  }
}

TEST(Quantization, EveryFloat32OfAUtmPlacedCloudRoundTripsExactly) {
  Bounds3 b;
  b.extend(500000.0, 5000000.0, -20.0);
  b.extend(501000.0, 5001000.0, 300.0);
  Quantization q = chooseQuantization(b, 16.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> ux(500000.f, 501000.f), uz(-20.f, 300.f);
  for (int i = 0; i < 10000; ++i) {
    float x = ux(rng), z = uz(rng);
    if (std::abs(z) < 320.f * 16.f / 128.f) continue;  // below the documented exact range
    EXPECT_EQ(float(q.toWorld(0, q.toQuantized(0, x))), x);
    EXPECT_EQ(float(q.toWorld(2, q.toQuantized(2, z))), z);
  }
}

TEST(Quantization, MarginWidensTheRange) {
  Bounds3 b;
  b.extend(0.0, 0.0, 0.0);
  b.extend(10.0, 10.0, 10.0);
  Quantization tight = chooseQuantization(b, 1.0);
  Quantization wide = chooseQuantization(b, 16.0);
  EXPECT_GT(wide.scale[0], tight.scale[0]);
  EXPECT_FALSE(tight.fits(0, 1000.0));
  EXPECT_TRUE(wide.fits(0, 80.0));
}

TEST(Quantization, OutOfRangeValuesClampInsteadOfOverflowing) {
  Quantization q;  // identity
  EXPECT_EQ(q.toQuantized(0, 1e12), Quantization::kMax);
  EXPECT_EQ(q.toQuantized(0, -1e12), Quantization::kMin);
  EXPECT_EQ(q.toQuantized(0, std::nan("")), Quantization::kMin);
  EXPECT_FALSE(q.fits(0, 1e12));
}

TEST(Quantization, FlatAxisGetsAUsableScale) {
  Bounds3 b;
  b.extend(5.0, 1.0, 7.0);
  b.extend(5.0, 2.0, 7.0);
  Quantization q = chooseQuantization(b);
  EXPECT_GT(q.scale[0], 0.0);
  EXPECT_EQ(q.toWorld(0, q.toQuantized(0, 5.0)), 5.0);
}

}  // namespace
}  // namespace parallax

namespace parallax {
namespace {

TEST(Quantization, CoordinatesNearTheLargestDoubleStayFinite) {
  Bounds3 b;
  b.extend(-1.7e308, -1.0, 0.0);
  b.extend(1.7e308, 1.0, 0.0);
  Quantization q = chooseQuantization(b, 16.0);
  EXPECT_TRUE(std::isfinite(q.scale[0]));
  EXPECT_TRUE(std::isfinite(q.offset[0]));
  EXPECT_TRUE(q.fits(0, 1.7e308));
  EXPECT_TRUE(q.fits(0, -1.7e308));
}

}  // namespace
}  // namespace parallax
