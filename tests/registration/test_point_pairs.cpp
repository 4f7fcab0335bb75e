// rigidTransformFromPairs: a known motion recovered from three and from five picked pairs of a
// georeferenced site, the least-squares fit of noisy pairs, and the degenerate picks as errors.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "registration/point_pairs.h"

namespace parallax {
namespace {

using PickedPoint = std::array<double, 3>;

// A 37-degree turn about a tilted axis and a shift of hundreds of metres, at UTM-sized coordinates.
RigidTransform pairsKnownMotion() {
  return RigidTransform::translation(-120.5, 340.25, 7.75) *
         RigidTransform::rotation(0.2, -0.3, 1.0, 37.0);
}

std::vector<PickedPoint> movedByMotion(const RigidTransform& t,
                                       const std::vector<PickedPoint>& points) {
  std::vector<PickedPoint> out;
  for (const auto& p : points) out.push_back(t.apply(p));
  return out;
}

std::string pairErrorOf(const std::vector<PickedPoint>& source,
                        const std::vector<PickedPoint>& target) {
  try {
    rigidTransformFromPairs(source, target);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(PointPairs, ThreePairsRecoverAKnownMotionAtUtmCoordinates) {
  const std::vector<PickedPoint> source{
      {512000.125, 4100000.5, 120.0}, {512030.0, 4100004.0, 123.5}, {512010.0, 4100025.0, 118.0}};
  const RigidTransform truth = pairsKnownMotion();
  const PairFit fit = rigidTransformFromPairs(source, movedByMotion(truth, source));
  // The targets hold the rounding of coordinates of 4e6 (5e-10 m) over 30 m between picks.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(fit.transform.m[i][j], truth.m[i][j], 1e-10);
  }
  // Any point of the site, not only the picked ones, lands where the known motion puts it.
  const PickedPoint far{512500.0, 4100400.0, 90.0};
  const PickedPoint a = fit.transform.apply(far), b = truth.apply(far);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], 1e-6);
  EXPECT_LT(fit.rms, 1e-8);
  EXPECT_NEAR(fit.transform.angleDegrees(), 37.0, 1e-9);
}

TEST(PointPairs, NoisyPairsGiveTheLeastSquaresFitAndItsRms) {
  // Five pairs, each target moved off by a known error; the errors sum to zero and are
  // orthogonal to the motion's six directions only approximately, so the fit lands near the
  // truth and its RMS is at most the errors' own.
  const std::vector<PickedPoint> source{
      {0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}, {10, 10, 10}};
  const RigidTransform truth = pairsKnownMotion();
  std::vector<PickedPoint> target = movedByMotion(truth, source);
  const std::vector<PickedPoint> error{
      {0.01, 0, 0}, {-0.01, 0.005, 0}, {0, -0.005, 0.01}, {0, 0, -0.01}, {0, 0, 0}};
  double error_rms = 0.0;
  for (std::size_t k = 0; k < target.size(); ++k) {
    for (int i = 0; i < 3; ++i) {
      target[k][i] += error[k][i];
      error_rms += error[k][i] * error[k][i];
    }
  }
  error_rms = std::sqrt(error_rms / 5.0);
  const PairFit fit = rigidTransformFromPairs(source, target);
  EXPECT_GT(fit.rms, 0.0);
  EXPECT_LE(fit.rms, error_rms + 1e-12);  // the truth's own RMS is error_rms: the best is no worse
  EXPECT_LT((truth.inverse() * fit.transform).angleDegrees(), 0.1);
  // A proper rotation, never a reflection: det R = 1.
  const auto& m = fit.transform.m;
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  EXPECT_NEAR(det, 1.0, 1e-12);
}

TEST(PointPairs, TooFewUnequalOrCollinearPicksAreErrorsSayingWhatToDo) {
  const std::vector<PickedPoint> two{{0, 0, 0}, {1, 0, 0}};
  EXPECT_NE(pairErrorOf(two, two).find("2 pairs; three are needed"), std::string::npos);
  const std::vector<PickedPoint> three{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_NE(pairErrorOf(three, two).find("3 source points but 2 target points"), std::string::npos);
  const std::vector<PickedPoint> line{{500000, 0, 0}, {500001, 1, 1}, {500003, 3, 3}};
  EXPECT_NE(pairErrorOf(line, line).find("lie on one line"), std::string::npos);
  EXPECT_EQ(pairErrorOf(three, three), "(no error)");
}

}  // namespace
}  // namespace parallax
