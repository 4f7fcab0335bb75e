// The plane of a neighbourhood by principal component analysis: the normal is the eigenvector of
// the covariance matrix's smallest eigenvalue (Hoppe et al. 1992, as Open3D's estimate_normals
// and PCL's NormalEstimation compute it), the curvature its share of the eigenvalues' sum,
// lambda0 / (lambda0 + lambda1 + lambda2) (Pauly et al. 2002, PCL's "surface variation").
#pragma once

#include <span>

#include "process/neighbour_index.h"

namespace parallax {

struct LocalPlane {
  double centroid[3] = {0, 0, 0};
  double normal[3] = {0, 0, 1};  // unit length, sign arbitrary (see orientation)
  double curvature = 0.0;        // 0 (flat) to 1/3 (isotropic)
  bool valid = false;            // false: fewer than 3 points, or all on one line
};

// The plane of the neighbours of `points` (a grid's points(), `Neighbour::at` into it), summed
// in the neighbours' order: the same neighbours in the same order give the same bits.
LocalPlane fitLocalPlane(std::span<const GridPoint> points, std::span<const Neighbour> neighbours);
// The same plane, the same bits, reading the neighbours from the index's tree order
// (`Neighbour::in_tree`): the neighbours' positions lie together there.
LocalPlane fitLocalPlane(const NeighbourIndex& index, std::span<const Neighbour> neighbours);

// Eigen decomposition of a symmetric 3x3 matrix (cyclic Jacobi rotations): eigenvalues in
// ascending order, eigenvector i in column i of `vectors`. The reference the closed form below
// is tested against.
void symmetricEigen3(const double matrix[3][3], double values[3], double vectors[3][3]);

// The eigenvalues of a symmetric 3x3 matrix in ascending order and a unit eigenvector of the
// smallest, in closed form: the roots of the characteristic polynomial by the trigonometric
// method (Smith 1961), the vector as the largest cross product of two rows of A - lambda0 I (as
// Open3D's estimate_normals computes it). Several times faster than Jacobi. The vector's error
// is about the rounding of A's eigenvalues over the gap lambda1 - lambda0: small for the flat
// neighbourhoods normals are about; where the gap is under 1e-6 of the eigenvalues' scale (a
// line, a ball) it falls back to Jacobi. lambda0 is the vector's Rayleigh quotient, to rounding
// level; lambda1 and lambda2 only to about 1e-8 of the scale where they nearly meet (a double
// root of the characteristic polynomial). Tested against symmetricEigen3.
void smallestEigen3(const double matrix[3][3], double values[3], double vector[3]);

}  // namespace parallax
