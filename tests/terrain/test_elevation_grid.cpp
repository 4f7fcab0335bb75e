// ElevationGrid and the square-window morphology against their definitions computed here by
// brute force, on small grids written in the test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "terrain/elevation_grid.h"
#include "terrain/morphology.h"

namespace parallax {
namespace {

// A filled grid of pseudo-random heights (SplitMix64 of the cell index: the same everywhere).
ElevationGrid randomGrid(std::size_t nx, std::size_t ny) {
  ElevationGrid grid(0.0, 0.0, 1.0, nx, ny);
  for (std::size_t c = 0; c < grid.cells(); ++c) {
    std::uint64_t z = (c + 1) * 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    grid.values()[c] = double(z >> 40) / double(1 << 24) * 10.0;
  }
  return grid;
}

// The extreme over the clipped square of radius r, cell by cell.
ElevationGrid bruteForce(const ElevationGrid& grid, std::size_t r, bool minimum) {
  ElevationGrid out = grid;
  for (std::size_t j = 0; j < grid.ny(); ++j) {
    for (std::size_t i = 0; i < grid.nx(); ++i) {
      double best = grid.at(i, j);
      for (std::size_t b = j < r ? 0 : j - r; b <= std::min(grid.ny() - 1, j + r); ++b) {
        for (std::size_t a = i < r ? 0 : i - r; a <= std::min(grid.nx() - 1, i + r); ++a) {
          best = minimum ? std::min(best, grid.at(a, b)) : std::max(best, grid.at(a, b));
        }
      }
      out.at(i, j) = best;
    }
  }
  return out;
}

TEST(ElevationGrid, CellsAreHalfOpenFromTheMinimumCornerAndTheMaximumFallsInTheLast) {
  const ElevationGrid grid = ElevationGrid::covering(10.0, 20.0, 13.0, 21.5, 1.0);
  EXPECT_EQ(grid.nx(), 4u);  // 10-11, 11-12, 12-13 and 13 itself
  EXPECT_EQ(grid.ny(), 2u);
  EXPECT_EQ(ElevationGrid::cellsCovering(10.0, 20.0, 13.0, 21.5, 1.0), 8.0);
  EXPECT_EQ(grid.column(10.0), 0u);
  EXPECT_EQ(grid.column(10.999), 0u);
  EXPECT_EQ(grid.column(11.0), 1u);
  EXPECT_EQ(grid.column(13.0), 3u);
  EXPECT_EQ(grid.column(9.0), 0u);  // clamped
  EXPECT_EQ(grid.row(21.5), 1u);
}

TEST(ElevationGrid, MinimumSurfaceKeepsTheLowestPointOfEachCell) {
  ElevationGrid grid(0.0, 0.0, 2.0, 2, 1);
  grid.addMinimum(0.5, 0.5, 3.0);
  grid.addMinimum(1.5, 0.5, 1.0);
  grid.addMinimum(1.9, 0.1, 2.0);
  EXPECT_EQ(grid.at(0, 0), 1.0);
  EXPECT_TRUE(ElevationGrid::empty(grid.at(1, 0)));
}

TEST(ElevationGrid, FillTakesTheMeanOfFilledNeighboursRingByRing) {
  // 5 x 1: filled at both ends; ring 1 is cells 1 and 3, ring 2 is cell 2 (the mean of 1 and 3).
  ElevationGrid line(0.0, 0.0, 1.0, 5, 1);
  line.at(0, 0) = 2.0;
  line.at(4, 0) = 6.0;
  line.fillEmpty();
  EXPECT_EQ(line.at(1, 0), 2.0);
  EXPECT_EQ(line.at(3, 0), 6.0);
  EXPECT_EQ(line.at(2, 0), 4.0);
  // 3 x 3 with the centre and one corner filled: every other cell touches the centre.
  ElevationGrid square(0.0, 0.0, 1.0, 3, 3);
  square.at(1, 1) = 1.0;
  square.at(0, 0) = 4.0;
  square.fillEmpty();
  EXPECT_EQ(square.at(1, 0), 2.5);  // neighbours (0,0) and (1,1)
  EXPECT_EQ(square.at(2, 2), 1.0);  // only the centre
  EXPECT_EQ(square.at(2, 0), 1.0);
  // Nothing filled: nothing to fill from.
  ElevationGrid none(0.0, 0.0, 1.0, 2, 2);
  none.fillEmpty();
  EXPECT_TRUE(ElevationGrid::empty(none.at(1, 1)));
}

TEST(ElevationGrid, BilinearSampleAndSlopeOfAPlaneAreExact) {
  // z = 3 + 0.25 x - 0.5 y at the cell centres: bilinear interpolation reproduces a plane, and
  // clamps to the edge cells' values outside the centres.
  ElevationGrid grid(100.0, 200.0, 2.0, 6, 4);
  auto plane = [](double x, double y) { return 3.0 + 0.25 * (x - 100.0) - 0.5 * (y - 200.0); };
  for (std::size_t j = 0; j < 4; ++j) {
    for (std::size_t i = 0; i < 6; ++i) grid.at(i, j) = plane(101.0 + 2.0 * i, 201.0 + 2.0 * j);
  }
  EXPECT_NEAR(grid.sample(104.3, 203.7), plane(104.3, 203.7), 1e-12);
  EXPECT_NEAR(grid.sample(111.0, 207.0), plane(111.0, 207.0), 1e-12);
  EXPECT_NEAR(grid.sample(100.0, 200.0), plane(101.0, 201.0), 1e-12);  // clamped to (0, 0)
  const ElevationGrid slope = grid.slope();
  for (double s : slope.values()) EXPECT_NEAR(s, std::sqrt(0.25 * 0.25 + 0.5 * 0.5), 1e-12);
}

TEST(Morphology, ErosionAndDilationEqualTheSquareWindowsExtremes) {
  for (std::size_t r : {1u, 2u, 5u, 40u}) {
    const ElevationGrid grid = randomGrid(23, 17);
    EXPECT_EQ(erode(grid, r).values(), bruteForce(grid, r, true).values()) << "r " << r;
    EXPECT_EQ(dilate(grid, r).values(), bruteForce(grid, r, false).values()) << "r " << r;
    EXPECT_EQ(open(grid, r).values(), bruteForce(bruteForce(grid, r, true), r, false).values());
  }
}

TEST(Morphology, OpeningRemovesWhatIsNarrowerThanTheWindow) {
  // A 3-cell-wide box on flat ground: gone at radius 2 (a 5-cell window), kept at radius 1.
  ElevationGrid grid(0.0, 0.0, 1.0, 12, 12);
  for (double& v : grid.values()) v = 0.0;
  for (std::size_t j = 4; j < 7; ++j) {
    for (std::size_t i = 4; i < 7; ++i) grid.at(i, j) = 5.0;
  }
  EXPECT_EQ(open(grid, 1).values(), grid.values());
  const ElevationGrid opened = open(grid, 2);
  for (double v : opened.values()) EXPECT_EQ(v, 0.0);
}

}  // namespace
}  // namespace parallax
