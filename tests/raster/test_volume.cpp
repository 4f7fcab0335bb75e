// Volumes of analytic piles on a sloped base within 0.5 % of their closed forms: a cone
// (pi a^2 h / 3), a box (w d h) and a paraboloid (pi a^2 h / 2), and a pit (fill) beside a pile
// (cut) on flat ground.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <sstream>

#include "core/error.h"
#include "io/las_writer.h"
#include "io/point_file.h"
#include "raster/geotiff.h"
#include "raster/volume.h"
#include "raster/volume_piles.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::cone;
using test::Height;
using test::slopedBase;
using test::slopedBaseRaster;
using test::TempDir;
using test::writeCloud;

double paraboloid(double x, double y) {  // radius 7, height 3, at (10, 10)
  const double r2 = (x - 10) * (x - 10) + (y - 10) * (y - 10);
  return r2 < 49 ? 3 * (1 - r2 / 49) : 0;
}
double box(double x, double y) {  // 4 x 6, 2 high
  return x >= 6 && x < 10 && y >= 5 && y < 11 ? 2 : 0;
}

VolumeOptions squareAround(const std::filesystem::path& cloud, double resolution) {
  VolumeOptions options;
  options.input.path = cloud;
  options.polygon = {{0, 0}, {20, 0}, {20, 20}, {0, 20}};
  options.resolution = resolution;
  return options;
}

TEST(Volume, AConeOnASlopedBaseAboveItsBoundaryPlane) {
  TempDir dir;
  const auto cloud = writeCloud(dir, slopedBase, cone, 0.1, 1);
  const VolumeReport r = computeVolume(squareAround(cloud, 0.1));
  const double expected = std::numbers::pi * 64 * 4 / 3;
  EXPECT_NEAR(r.cut, expected, 0.005 * expected);
  EXPECT_NEAR(r.fill, 0.0, 0.001 * expected);
  EXPECT_NEAR(r.net, expected, 0.005 * expected);
  EXPECT_NEAR(r.plane_a, 0.1, 1e-5);
  EXPECT_NEAR(r.plane_b, 0.05, 1e-5);
  EXPECT_NEAR(r.plane_c, 20.0, 1e-3);
  EXPECT_EQ(r.cells, 200u * 200u);
  EXPECT_NEAR(r.area, 400.0, 1e-9);
}

TEST(Volume, ABoxAndAParaboloid) {
  TempDir dir;
  const auto box_cloud = writeCloud(dir, slopedBase, box, 0.1, 1);
  const VolumeReport b = computeVolume(squareAround(box_cloud, 0.1));
  EXPECT_NEAR(b.net, 48.0, 0.005 * 48.0);
  const auto hill = writeCloud(dir, slopedBase, paraboloid, 0.1, 1);
  const VolumeReport p = computeVolume(squareAround(hill, 0.1));
  const double expected = std::numbers::pi * 49 * 3 / 2;
  EXPECT_NEAR(p.net, expected, 0.005 * expected);
}

TEST(Volume, ADenseCloudWithTheMeanSurface) {
  // Nine points a cell of 0.2: the mean of a cell is its centre's height on a plane, so only
  // the cone's curvature is left. (The max would sit up the slope: see volume.h.)
  TempDir dir;
  const auto cloud = writeCloud(dir, slopedBase, cone, 0.2, 3);
  VolumeOptions options = squareAround(cloud, 0.2);
  options.surface = RasterValue::Mean;
  const VolumeReport r = computeVolume(options);
  const double expected = std::numbers::pi * 64 * 4 / 3;
  EXPECT_NEAR(r.net, expected, 0.005 * expected);
  EXPECT_EQ(r.points_used, 100u * 100u * 9 + 2 * 100u * 9 + 9);  // the cells of [0, 20.2)^2
}

TEST(Volume, CutAndFillAgainstTheLowestRingSampleAndARasterBase) {
  TempDir dir;
  const auto flat = [](double, double) { return 5.0; };
  // A cone pile at (8, 8) (cut) and a paraboloid pit 1 deep of radius 2.5 at (16.5, 16.5)
  // (fill), apart.
  const auto terrain = [](double x, double y) {
    const double r2 = (x - 16.5) * (x - 16.5) + (y - 16.5) * (y - 16.5);
    return cone(x + 2, y + 2) - (r2 < 6.25 ? 1 - r2 / 6.25 : 0);
  };
  const auto cloud = writeCloud(dir, flat, terrain, 0.1, 1);
  VolumeOptions options = squareAround(cloud, 0.1);
  options.base = VolumeBase::Lowest;
  const VolumeReport r = computeVolume(options);
  const double pile = std::numbers::pi * 64 * 4 / 3, pit = std::numbers::pi * 6.25 / 2;
  EXPECT_EQ(r.plane_c, 5.0);
  EXPECT_NEAR(r.cut, pile, 0.005 * pile);
  EXPECT_NEAR(r.fill, pit, 0.005 * pit);
  EXPECT_NEAR(r.net, pile - pit, 0.005 * pile);

  // The same against a base raster at z = 4 (a coarser grid): one more unit over 400.
  RasterImage base;
  base.grid = boundedGrid(-5, -5, 25, 25, 1.0);
  base.values.assign(base.grid.cellCount(), 4.0f);
  writeGeoTiff(base, dir / "base.tif");
  options.base = VolumeBase::Raster;
  options.base_raster = dir / "base.tif";
  options.raster_out = dir / "difference.tif";
  const VolumeReport above = computeVolume(options);
  EXPECT_NEAR(above.net, pile - pit + 400.0, 0.005 * pile);
  const RasterImage difference = readRaster(dir / "difference.tif");
  EXPECT_TRUE(sameGrid(difference.grid, above.grid));
  EXPECT_FLOAT_EQ(difference.at(190, 190), 1.0f);         // (19.05, 1.05): flat ground, 5 - 4
  EXPECT_EQ(difference.at(200, 100), difference.nodata);  // x = 20.05: outside the polygon
}

// The sloped base as a raster under the cone (slopedBaseRaster): the cone's volume, as above the
// plane fitted along the ring.
TEST(Volume, AConeAboveABaseRasterOfTheSlope) {
  TempDir dir;
  const auto cloud = writeCloud(dir, slopedBase, cone, 0.5, 1);
  writeGeoTiff(slopedBaseRaster(-1, -1, 21, 21), dir / "base.tif");
  VolumeOptions options = squareAround(cloud, 0.5);
  setVolumeBase(options, (dir / "base.tif").string());
  ASSERT_EQ(options.base, VolumeBase::Raster);
  const VolumeReport r = computeVolume(options);
  const double expected = std::numbers::pi * 64 * 4 / 3;
  EXPECT_NEAR(r.cut, expected, 0.005 * expected);
  // The base at the cells' centres is the surface there away from the cone (both the plane in
  // float): nothing below it beyond float rounding.
  EXPECT_NEAR(r.fill, 0.0, 1e-3);
  EXPECT_EQ(r.cells, 40u * 40u);
  EXPECT_EQ(r.cells_without_base, 0u);
  setVolumeBase(options, "lowest");
  EXPECT_EQ(options.base, VolumeBase::Lowest);
  setVolumeBase(options, "plane");
  EXPECT_EQ(options.base, VolumeBase::Plane);
}

// The message of what computeVolume throws for `options` (empty when it throws nothing).
template <typename Error>
std::string volumeError(const VolumeOptions& options) {
  try {
    computeVolume(options);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Volume, ABaseRasterThatIsMissingShortOrInAnotherCrsIsAnError) {
  TempDir dir;
  const auto cloud = writeCloud(dir, slopedBase, cone, 0.5, 1);
  VolumeOptions options = squareAround(cloud, 0.5);
  setVolumeBase(options, (dir / "none.tif").string());
  const std::string missing = volumeError<std::invalid_argument>(options);
  EXPECT_NE(missing.find("--base"), std::string::npos) << missing;
  EXPECT_NE(missing.find("none.tif' (no such file)"), std::string::npos) << missing;

  // Covering x up to 15 only: the polygon's cells from x = 15.25 to 19.75 are beyond it.
  writeGeoTiff(slopedBaseRaster(-1, -1, 15, 21), dir / "short.tif");
  setVolumeBase(options, (dir / "short.tif").string());
  const std::string short_of = volumeError<InputError>(options);
  EXPECT_NE(short_of.find("short.tif"), std::string::npos) << short_of;
  EXPECT_NE(short_of.find("x [-1, 15], y [-1, 21], and 400 cell centres inside the polygon "
                          "beyond it (x [15.25, 19.75], y [0.25, 19.75])"),
            std::string::npos)
      << short_of;

  // Nodata at every cell inside the polygon.
  RasterImage empty = slopedBaseRaster(-1, -1, 21, 21);
  empty.values.assign(empty.values.size(), empty.nodata);
  writeGeoTiff(empty, dir / "empty.tif");
  setVolumeBase(options, (dir / "empty.tif").string());
  const std::string no_values = volumeError<InputError>(options);
  EXPECT_NE(no_values.find("empty.tif"), std::string::npos) << no_values;
  EXPECT_NE(no_values.find("nodata at all 1600 of them"), std::string::npos) << no_values;

  // The cloud in UTM 32N (a LAS file with its GeoTIFF keys), the raster in UTM 33N.
  std::string keys;
  for (std::uint16_t v : {1, 1, 0, 1, 3072, 0, 1, 32632}) {
    keys.append(reinterpret_cast<const char*>(&v), 2);
  }
  LasVlr projection{.user_id = "LASF_Projection", .record_id = 34735};
  for (char c : keys) projection.data.push_back(std::byte(c));
  const auto las = dir / "cloud.las";
  writeLas(readPointFile(cloud), las, {.vlrs = {projection}});
  RasterImage utm33 = slopedBaseRaster(-1, -1, 21, 21);
  CoordinateSystem crs;
  crs.description.projected_epsg = 32633;
  utm33.wkt = wktOfCoordinateSystem(crs);
  writeGeoTiff(utm33, dir / "utm33.tif");
  options.input.path = las;
  setVolumeBase(options, (dir / "utm33.tif").string());
  const std::string other_crs = volumeError<InputError>(options);
  EXPECT_NE(other_crs.find("utm33.tif"), std::string::npos) << other_crs;
  EXPECT_NE(other_crs.find("expected the cloud's CRS, WGS 84 / UTM zone 32N (EPSG:32632), found "
                           "WGS 84 / UTM zone 33N (EPSG:32633)"),
            std::string::npos)
      << other_crs;
  // The same raster in the cloud's CRS: the cone's volume again.
  crs.description.projected_epsg = 32632;
  utm33.wkt = wktOfCoordinateSystem(crs);
  writeGeoTiff(utm33, dir / "utm32.tif");
  setVolumeBase(options, (dir / "utm32.tif").string());
  const double expected = std::numbers::pi * 64 * 4 / 3;
  EXPECT_NEAR(computeVolume(options).cut, expected, 0.005 * expected);
}

// A grid beyond any machine's memory (1e16 cells at 1e-5 over 1000 x 1000; 1000 / 1e-5 rounds
// below 1e8, so no extra column) is an error that names --resolution, said before the cloud is
// read; it was a bare std::bad_alloc ("out of memory").
TEST(Volume, AGridOverTheMachinesMemoryIsAnErrorNamingTheResolution) {
  TempDir dir;
  VolumeOptions options = squareAround(writeCloud(dir, slopedBase, cone, 0.5, 1), 1e-5);
  options.polygon = {{0, 0}, {1000, 0}, {1000, 1000}, {0, 1000}};
  const std::string message = volumeError<std::invalid_argument>(options);
  EXPECT_EQ(message.rfind("--resolution 1e-05: the polygon's bounding box (1000 x 1000) makes "
                          "100000000 x 100000000 cells, 152587890625 MB held whole",
                          0),
            0u)
      << message;
}

// A negative or non-finite --fill-radius is refused as raster refuses it; it was taken as the
// default (10 cells) without a word.
TEST(Volume, ANegativeFillRadiusIsAnError) {
  TempDir dir;
  VolumeOptions options = squareAround(writeCloud(dir, slopedBase, cone, 0.5, 1), 0.5);
  options.fill_radius = -1.0;
  EXPECT_EQ(volumeError<std::invalid_argument>(options),
            "--fill-radius: expected a positive distance, found -1.000000");
  options.fill_radius = std::nan("");
  EXPECT_EQ(volumeError<std::invalid_argument>(options),
            "--fill-radius: expected a positive distance, found nan");
}

// --raster-out naming the input cloud, or in a missing folder, is refused before any work.
TEST(Volume, ARasterOutThatIsTheInputOrInAMissingFolderIsAnError) {
  TempDir dir;
  const auto cloud = writeCloud(dir, slopedBase, cone, 0.5, 1);
  const std::uintmax_t size = std::filesystem::file_size(cloud);
  VolumeOptions options = squareAround(cloud, 0.5);
  options.raster_out = cloud;
  EXPECT_EQ(
      volumeError<std::invalid_argument>(options),
      "--raster-out " + cloud.string() +
          ": is the input point file, which the GeoTIFF would replace: expected another file");
  EXPECT_EQ(std::filesystem::file_size(cloud), size);
  // A raster in a folder that does not exist: said before the work (it was GDAL's error after
  // it), as raster says it of -o.
  options.raster_out = dir / "missing" / "d.tif";
  EXPECT_EQ(volumeError<std::invalid_argument>(options),
            "--raster-out " + options.raster_out.string() + ": the folder " +
                (dir / "missing").string() + " does not exist");
}

// raster's GDAL block cache is within --memory (an eighth of it, at most 64 MB): left at GDAL's
// default (5 % of the machine's memory) it took B2.e57 at 1e-6 to 3.0 GB resident at 2048 MB.
TEST(RasterMemory, GdalsBlockCacheIsAnEighthOfTheBudget) {
  TempDir dir;
  RasterOptions options;
  options.input.path = writeCloud(dir, slopedBase, cone, 0.5, 1);
  options.output = dir / "r.tif";
  options.resolution = 1.0;
  options.memory_mb = 16;
  buildRaster(options);
  EXPECT_EQ(gdalCacheLimit(), 2u << 20);
  EXPECT_TRUE(std::filesystem::exists(dir / "r.tif"));
}

TEST(Volume, FitPlaneNeedsThreePointsNotOnALine) {
  double a, b, c;
  EXPECT_FALSE(fitPlane({{0, 0, 1}, {1, 1, 2}}, a, b, c));
  EXPECT_FALSE(fitPlane({{0, 0, 1}, {1, 1, 2}, {2, 2, 3}}, a, b, c));
  ASSERT_TRUE(
      fitPlane({{500000, 4000000, 1}, {500001, 4000000, 3}, {500000, 4000001, 0.5}}, a, b, c));
  EXPECT_NEAR(a, 2.0, 1e-9);
  EXPECT_NEAR(b, -0.5, 1e-9);
}

}  // namespace
}  // namespace parallax
