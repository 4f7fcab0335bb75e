// The point budget that follows the headset's frame time (xr/frame_budget.h).
#include "xr/frame_budget.h"

#include <gtest/gtest.h>

namespace parallax {
namespace {

constexpr double kPeriod = 1.0 / 90.0;

TEST(FrameBudget, ShrinksInProportionToTheTimeThereIs) {
  FrameBudget budget({.most = 1'000'000, .least = 10'000});
  EXPECT_EQ(budget.budget(), 1'000'000u);
  // 0.8 of the period is there; a frame of the whole period gets 0.8 of the points.
  EXPECT_NEAR(double(budget.update(kPeriod, kPeriod, 1'000'000)), 800'000.0, 1.0);
  // Four times too slow: halved, not quartered, in one frame.
  EXPECT_NEAR(double(budget.update(4 * kPeriod, kPeriod, budget.budget())), 400'000.0, 1.0);
}

TEST(FrameBudget, GrowsByATenthWhileFramesAreFastUpToTheAskedBudget) {
  FrameBudget budget({.most = 1'000'000, .least = 10'000});
  budget.update(2 * kPeriod, kPeriod, 1'000'000);
  EXPECT_EQ(budget.budget(), 500'000u);
  EXPECT_EQ(budget.update(0.3 * kPeriod, kPeriod, 500'000), 550'000u);
  // Within the period but not well under it: kept.
  EXPECT_EQ(budget.update(0.7 * kPeriod, kPeriod, 550'000), 550'000u);
  // A frame that did not fill the budget says nothing about a larger one.
  EXPECT_EQ(budget.update(0.1 * kPeriod, kPeriod, 100'000), 550'000u);
  for (int i = 0; i < 20; ++i) budget.update(0.1 * kPeriod, kPeriod, budget.budget());
  EXPECT_EQ(budget.budget(), 1'000'000u);
}

TEST(FrameBudget, NeverBelowTheFloor) {
  FrameBudget budget({.most = 1'000'000, .least = 200'000});
  for (int i = 0; i < 10; ++i) budget.update(10 * kPeriod, kPeriod, budget.budget());
  EXPECT_EQ(budget.budget(), 200'000u);
}

}  // namespace
}  // namespace parallax
