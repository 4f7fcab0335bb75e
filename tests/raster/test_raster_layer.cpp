// A raster shown with a cloud (raster/raster_layer.h): the layer's points against the cells, and
// `parallax render CLOUD --raster DEM.tif` from above: at the pixel where each cell's centre
// projects (an orthographic projection worked out here), the cell's colour, the grey ramp at its
// height shaded by the hillshade of the plane, both computed here from the plane's equation.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "raster/geotiff.h"
#include "raster/raster_layer.h"
#include "raster/raster_plane_scene.h"
#include "render/image_file.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

using test::readText;
using test::runWithoutLeakCheck;

TEST(RasterLayer, APointPerCellWithAValueAtItsCentreAndHeight) {
  const RasterImage raster = planeRaster();
  const auto [low, high] = rasterValueRange(raster);
  EXPECT_DOUBLE_EQ(low, plane(0.5, 0.5));
  EXPECT_DOUBLE_EQ(high, plane(kColumns - 0.5, kRows - 0.5));
  const PointCloud points = rasterLayerPoints(raster, {.ramp = greyRamp, .low = low, .high = high});
  ASSERT_EQ(points.count, std::size_t(kColumns * kRows - 1));
  // The first point: column 0, row 0 (the top-left cell).
  EXPECT_NEAR(points.worldX(0), 0.5, 1e-9);
  EXPECT_NEAR(points.worldY(0), kRows - 0.5, 1e-9);
  EXPECT_NEAR(points.worldZ(0), plane(0.5, kRows - 0.5), 1e-3);
  // An interior cell (column 5, row 2; the hole at (3, 4) comes later): the plane's shade.
  const std::size_t i = 2 * kColumns + 5;
  EXPECT_NEAR(points.worldX(i), 5.5, 1e-9);
  EXPECT_NEAR(points.worldY(i), kRows - 2.5, 1e-9);
  EXPECT_NEAR(points.colors[i].r, expectedGrey(plane(5.5, kRows - 2.5), planeShade()), 1);
}

TEST(RenderRasterLayer, EachCellsColourAtItsProjectedCentre) {
  TempDir dir;
  const auto tif = dir / "plane.tif";
  writeGeoTiff(planeRaster(), tif);
  const auto ply = dir.write("corners.ply", cornersPly());
  const auto png = dir / "out.png";
  const auto log = dir / "log";
  const std::string command = std::string(PARALLAX_EXECUTABLE) + " render '" + ply.string() +
                              "' -o '" + png.string() + "' --raster '" + tif.string() + "' " +
                              kPlaneLayerLook + " 2>'" + log.string() + "'";
  ASSERT_EQ(runWithoutLeakCheck(command), 0) << readText(log);
  expectPlaneLayerPicture(readPng(png));
}

TEST(RenderRasterLayer, AFileThatIsNotARasterIsNamed) {
  TempDir dir;
  const auto ply = dir.write("corners.ply", cornersPly());
  const auto bad = dir.write("bad.tif", "not a raster");
  const auto log = dir / "log";
  const std::string command = std::string(PARALLAX_EXECUTABLE) + " render '" + ply.string() +
                              "' -o '" + (dir / "out.png").string() + "' --raster '" +
                              bad.string() + "' 2>'" + log.string() + "'";
  EXPECT_NE(runWithoutLeakCheck(command), 0);
  EXPECT_NE(readText(log).find(bad.string()), std::string::npos) << readText(log);
}

}  // namespace
}  // namespace parallax::test
