// The rigid transform that best takes a few picked source points onto their partners in the
// target: the initial transform of a registration from three (or more) pairs of points picked
// in the viewer, before ICP refines it.
//
// Least squares over the pairs by Horn's closed form (Horn 1987, "Closed-form solution of
// absolute orientation using unit quaternions"): the rotation is the unit quaternion of the
// largest eigenvalue of a 4x4 symmetric matrix built from the pairs' cross-covariance, so it is
// always a proper rotation (never a reflection), whatever the pairs' noise. Coordinates are world
// units in double, centred on each side's centroid before any product (UTM-sized coordinates keep
// their millimetres).
#pragma once

#include <array>
#include <span>

#include "registration/rigid_transform.h"

namespace parallax {

struct PairFit {
  RigidTransform transform;  // SOURCE -> TARGET: transform.apply(source[i]) ~ target[i]
  double rms = 0.0;          // root mean square of |transform.apply(source[i]) - target[i]|
};

// `source[i]` and `target[i]` are a pair. Throws std::invalid_argument when the sizes differ,
// there are fewer than 3 pairs, or the source points are (nearly) on one line (the rotation about
// that line is then free): the message says which, so a picking tool can ask for another point.
PairFit rigidTransformFromPairs(std::span<const std::array<double, 3>> source,
                                std::span<const std::array<double, 3>> target);

}  // namespace parallax
