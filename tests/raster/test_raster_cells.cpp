// The raster module's arithmetic on tiny inputs with values worked out by hand: the cell rule on
// edges, each value of a cell, inverse distance weighting, gap filling and shaded relief.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "raster/cell_accumulator.h"
#include "raster/hillshade.h"
#include "raster/raster_fill.h"
#include "raster/raster_grid.h"

namespace parallax {
namespace {

constexpr float kNo = kRasterNodata;

// A resolution so fine that a side passes 2^31 - 1 cells is refused with the smallest one that
// fits, before the count becomes an integer (1e-300 used to give a negative count and an empty
// raster written without error). 2^31 - 2 cells across an extent of 1 still fit.
TEST(RasterGrid, ASideOverGeoTiffsLimitIsAnErrorNamingTheResolution) {
  auto message = [](auto make) -> std::string {
    try {
      make();
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message([] { alignedGrid(0.0, 0.0, 1.0, 1.0, 1e-300); }),
            "--resolution 1e-300: the extent of 1 in x makes 1e+300 cells, over GeoTIFF's "
            "2147483647 a side: expected a resolution of at least 4.65661e-10");
  EXPECT_EQ(message([] { alignedGrid(0.0, 0.0, 0.0, 2.5, 1e-9); }),
            "--resolution 1e-09: the extent of 2.5 in y makes 2.5e+09 cells, over GeoTIFF's "
            "2147483647 a side: expected a resolution of at least 1.16415e-09");
  EXPECT_EQ(message([] { boundedGrid(0.0, 0.0, 1.0, 3.0, 1e-9); }),
            "--resolution 1e-09: the extent of 3 in y makes 3e+09 cells, over GeoTIFF's "
            "2147483647 a side: expected a resolution of at least 1.39698e-09");
  const RasterGrid widest = alignedGrid(0.0, 0.0, 1.0, 0.0, 1.0 / 2147483646.0);
  EXPECT_EQ(widest.columns, 2147483647);
  EXPECT_EQ(widest.rows, 1);
}

// More 256 x 256 tiles than a GeoTIFF's tile index holds (2^28) is refused naming --resolution:
// A4.e57 (0.65 x 0.46) at 1e-9 is under 2^31 - 1 cells a side and ended in GDAL's "File too
// large regarding tile size", which named neither (1 / 1e-9 rounds below 1e9: no extra cell).
// 16384 x 16384 tiles exactly still fit.
TEST(RasterGrid, MoreTilesThanAGeoTiffIndexHoldsIsAnErrorNamingTheResolution) {
  auto message = [](const RasterGrid& grid) -> std::string {
    try {
      checkGeoTiffTiles(grid);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message(alignedGrid(0.0, 0.0, 1.0, 1.0, 1e-9)),
            "--resolution 1e-09: the grid of 1000000000 x 1000000000 cells is 1.52588e+13 tiles "
            "of 256 x 256, over the 268435456 a GeoTIFF's tile index holds: expected a resolution "
            "of at least 2.38419e-07");
  EXPECT_EQ(message(alignedGrid(0.0, 0.0, 4194304.0, 4194303.0, 1.0)),
            "--resolution 1: the grid of 4194305 x 4194304 cells is 2.68452e+08 tiles of 256 x "
            "256, over the 268435456 a GeoTIFF's tile index holds: expected a resolution of at "
            "least 1.00003");
  EXPECT_EQ(message(alignedGrid(0.0, 0.0, 4194303.0, 4194303.0, 1.0)), "no error");
}

TEST(RasterGrid, EdgesAlignToTheResolutionAndAPointOnAnEdgeGoesRightAndUp) {
  const RasterGrid grid = alignedGrid(0.3, 0.7, 2.0, 2.9, 0.5);
  EXPECT_EQ(grid.left, 0.0);
  EXPECT_EQ(grid.bottom(), 0.5);
  EXPECT_EQ(grid.top, 3.0);
  // maxx = 2.0 lies on an edge: it belongs to a fifth column [2.0, 2.5).
  EXPECT_EQ(grid.columns, 5);
  EXPECT_EQ(grid.rows, 5);
  EXPECT_EQ(grid.columnOf(0.5), 1);  // on the edge between columns 0 and 1: the right one
  EXPECT_EQ(grid.columnOf(0.49), 0);
  EXPECT_EQ(grid.rowOf(1.0), 3);  // y in [1.0, 1.5): row 3 from the top
  EXPECT_EQ(grid.rowOf(0.99), 4);
  EXPECT_EQ(grid.rowOf(2.9), 0);
  EXPECT_EQ(grid.geoTransform(), (std::array<double, 6>{0.0, 0.5, 0.0, 3.0, 0.0, -0.5}));
  EXPECT_DOUBLE_EQ(grid.centreX(0), 0.25);
  EXPECT_DOUBLE_EQ(grid.centreY(0), 2.75);
  // Negative coordinates floor downwards.
  const RasterGrid negative = alignedGrid(-1.2, -0.1, -0.2, 0.0, 1.0);
  EXPECT_EQ(negative.left, -2.0);
  EXPECT_EQ(negative.bottom(), -1.0);
  EXPECT_EQ(negative.columns, 2);
  EXPECT_EQ(negative.rows, 2);
}

TEST(RasterGrid, BoundsGiveTheCornerAndCeilCells) {
  const RasterGrid grid = boundedGrid(10.0, 20.0, 12.5, 21.0, 1.0);
  EXPECT_EQ(grid.left, 10.0);
  EXPECT_EQ(grid.top, 21.0);
  EXPECT_EQ(grid.columns, 3);
  EXPECT_EQ(grid.rows, 1);
  EXPECT_TRUE(sameGrid(grid, boundedGrid(10.0, 20.0, 12.2, 20.5, 1.0)));
  EXPECT_FALSE(sameGrid(grid, boundedGrid(10.5, 20.0, 13.0, 21.0, 1.0)));
}

// A 2 x 2 grid of cells 0.5 wide from (0, 0): points in the top-left cell (x < 0.5, y >= 0.5)
// and the bottom-right one, none in the other two.
struct Points {
  double x, y, z;
  float intensity;
};
const Points kPoints[] = {
    {0.1, 0.6, 3.0, 10.0f}, {0.4, 0.9, 1.0, 20.0f}, {0.0, 0.5, 2.0, 60.0f},  // top-left
    {0.5, 0.0, -1.0, 5.0f}, {0.9, 0.4, 4.5, 7.0f},                           // bottom-right
};

std::vector<float> cellsOf(RasterValue value) {
  const RasterGrid grid = alignedGrid(0.0, 0.0, 0.99, 0.99, 0.5);
  CellAccumulator cells(grid, value, 0, grid.rows, 0.5);
  for (const Points& p : kPoints) cells.addPoint(p.x, p.y, p.z, p.intensity);
  return cells.values(kNo);
}

TEST(CellAccumulator, EachValueOfACell) {
  EXPECT_EQ(cellsOf(RasterValue::Min), (std::vector<float>{1.0f, kNo, kNo, -1.0f}));
  EXPECT_EQ(cellsOf(RasterValue::Max), (std::vector<float>{3.0f, kNo, kNo, 4.5f}));
  EXPECT_EQ(cellsOf(RasterValue::Mean), (std::vector<float>{2.0f, kNo, kNo, 1.75f}));
  EXPECT_EQ(cellsOf(RasterValue::Count), (std::vector<float>{3.0f, 0.0f, 0.0f, 2.0f}));
  // Points per square unit: 3 points in 0.25.
  EXPECT_EQ(cellsOf(RasterValue::Density), (std::vector<float>{12.0f, 0.0f, 0.0f, 8.0f}));
  EXPECT_EQ(cellsOf(RasterValue::Intensity), (std::vector<float>{30.0f, kNo, kNo, 6.0f}));
}

TEST(CellAccumulator, ABandHoldsOnlyItsRows) {
  const RasterGrid grid = alignedGrid(0.0, 0.0, 0.99, 0.99, 0.5);
  CellAccumulator bottom(grid, RasterValue::Max, 1, 2, 0.5);
  for (const Points& p : kPoints) bottom.addPoint(p.x, p.y, p.z, p.intensity);
  EXPECT_EQ(bottom.values(kNo), (std::vector<float>{kNo, 4.5f}));
  EXPECT_EQ(bottom.pointsUsed(), 2u);
}

TEST(CellAccumulator, IdwIsInverseDistanceSquaredWithinTheRadius) {
  // One cell centred on (0.5, 0.5).
  const RasterGrid grid = boundedGrid(0.0, 0.0, 1.0, 1.0, 1.0);
  CellAccumulator cells(grid, RasterValue::Idw, 0, 1, 0.5);
  cells.addPoint(0.8, 0.5, 1.0, 0);    // d^2 = 0.09
  cells.addPoint(0.5, 0.1, 4.0, 0);    // d^2 = 0.16
  cells.addPoint(0.5, 1.0, 9.0, 0);    // d = 0.5 exactly: inside (gdal_grid's closed ellipse)
  cells.addPoint(0.9, 0.9, 100.0, 0);  // d^2 = 0.32 > 0.25: outside
  const double expected =
      (1.0 / 0.09 + 4.0 / 0.16 + 9.0 / 0.25) / (1.0 / 0.09 + 1.0 / 0.16 + 1.0 / 0.25);
  EXPECT_FLOAT_EQ(cells.values(kNo)[0], float(expected));
  // A point on the centre decides the cell alone, whatever comes before or after it.
  cells.addPoint(0.5, 0.5, 7.0, 0);
  cells.addPoint(0.5, 0.5, 8.0, 0);
  EXPECT_EQ(cells.values(kNo)[0], 7.0f);
  CellAccumulator empty(grid, RasterValue::Idw, 0, 1, 0.1);
  empty.addPoint(0.9, 0.9, 1.0, 0);
  EXPECT_EQ(empty.values(kNo)[0], kNo);
}

TEST(RasterFill, GapsTakeTheInverseDistanceSquaredMeanOfTheValuesWithinTheRadius) {
  RasterImage image;
  image.grid = boundedGrid(0.0, 0.0, 4.0, 3.0, 1.0);  // 4 x 3
  image.values = {1, 2,   kNo, kNo,                   //
                  3, kNo, kNo, kNo,                   //
                  5, 6,   kNo, kNo};
  // Radius 1.5 cells: the 8 neighbours (d^2 = 1 or 2), not two cells away.
  EXPECT_EQ(fillNodata(image, 1.5), 4u);
  // (1, 1): orthogonal 2, 3, 6 (weight 1), diagonal 1, 5 (weight 1/2), from original values only.
  EXPECT_FLOAT_EQ(image.at(1, 1), float((2 + 3 + 6 + 0.5 * (1 + 5)) / (3 + 0.5 * 2)));
  // (2, 0): 2 (weight 1), the diagonal (1, 1) was a gap: nothing else.
  EXPECT_FLOAT_EQ(image.at(2, 0), 2.0f);
  EXPECT_FLOAT_EQ(image.at(2, 2), 6.0f);
  EXPECT_FLOAT_EQ(image.at(2, 1), 4.0f);  // 2 and 6 on the diagonals, the rest gaps
  EXPECT_EQ(image.at(3, 0), kNo);         // two cells from any value
  EXPECT_EQ(image.at(3, 1), kNo);
  EXPECT_EQ(image.at(3, 2), kNo);
}

RasterImage plane(double sx, double sy, double resolution) {
  RasterImage image;
  image.grid = boundedGrid(0.0, 0.0, 5 * resolution, 4 * resolution, resolution);
  image.values.resize(image.grid.cellCount());
  for (std::int64_t r = 0; r < image.grid.rows; ++r) {
    for (std::int64_t c = 0; c < image.grid.columns; ++c) {
      image.at(c, r) = float(sx * image.grid.centreX(c) + sy * image.grid.centreY(r));
    }
  }
  return image;
}

// The shade of a plane from the angle between its normal and the light, computed here from
// vectors: n = (-sx, -sy, 1) / |.|, light from azimuth 315 at altitude 45.
std::uint8_t shadeOfPlane(double sx, double sy) {
  const double alt = std::numbers::pi / 4, az = 315 * std::numbers::pi / 180;
  const double lx = std::sin(az) * std::cos(alt), ly = std::cos(az) * std::cos(alt);
  const double lz = std::sin(alt);
  const double cosine = (-sx * lx - sy * ly + lz) / std::sqrt(sx * sx + sy * sy + 1);
  return std::uint8_t(std::lround(cosine <= 0 ? 1.0 : 1.0 + 254.0 * cosine));
}

TEST(Hillshade, PlanesAreShadedByTheAngleToTheLightAndTheBorderIsEmpty) {
  for (const auto& [sx, sy] :
       {std::pair{0.0, 0.0}, {0.5, 0.0}, {0.0, 0.5}, {-1.0, 0.3}, {3.0, 3.0}}) {
    const RasterImage image = plane(sx, sy, 0.5);
    const std::vector<std::uint8_t> shade = hillshade(image);
    const auto at = [&](std::int64_t c, std::int64_t r) {
      return shade[std::size_t(r * image.grid.columns + c)];
    };
    EXPECT_EQ(at(2, 1), shadeOfPlane(sx, sy)) << sx << " " << sy;
    EXPECT_EQ(at(3, 2), shadeOfPlane(sx, sy)) << sx << " " << sy;
    EXPECT_EQ(at(0, 1), 0);
    EXPECT_EQ(at(4, 2), 0);
    EXPECT_EQ(at(2, 0), 0);
    EXPECT_EQ(at(2, 3), 0);
  }
  // Flat ground: 1 + 254 sin(45).
  EXPECT_EQ(shadeOfPlane(0, 0), 181);
  // Next to a gap: no value.
  RasterImage gap = plane(0.2, 0.1, 1.0);
  gap.at(1, 1) = kNo;
  const std::vector<std::uint8_t> shade = hillshade(gap);
  EXPECT_EQ(shade[std::size_t(1 * 5 + 2)], 0);
  EXPECT_EQ(shade[std::size_t(2 * 5 + 3)], shadeOfPlane(0.2, 0.1));
}

}  // namespace
}  // namespace parallax
