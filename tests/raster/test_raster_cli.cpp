// `parallax raster` as a user runs it, checked by GDAL's own tools on the same points:
// gdal_grid's minimum, maximum, average, count and invdist on the same grid, gdalinfo's account of the
// file (size, geotransform, CRS, nodata, tiles, compression, statistics) and gdaldem's hillshade.
#include <gdal.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "io/point_file.h"
#include "raster/geotiff.h"
#include "raster/raster_grid.h"
#include "support/run_parallax.h"
#include "support/test_data.h"

namespace parallax {
namespace {

using test::quoted;
using test::runParallax;
using test::TempDir;

struct Xyz {
  double x, y, z;
};

// Coordinates with three decimals, so that both readers parse the same numbers.
double round3(double v) {
  return std::round(v * 1000.0) / 1000.0;
}

// The points as a text file for Parallax and a CSV with its OGR VRT for gdal_grid.
std::filesystem::path writePoints(const TempDir& dir, const std::vector<Xyz>& points) {
  std::ostringstream text, csv;
  text.precision(3);
  csv.precision(3);
  text << std::fixed;
  csv << std::fixed << "x,y,z\n";
  for (const Xyz& p : points) {
    text << p.x << ' ' << p.y << ' ' << p.z << '\n';
    csv << p.x << ',' << p.y << ',' << p.z << '\n';
  }
  dir.write("pts.csv", csv.str());
  dir.write("pts.vrt", "<OGRVRTDataSource><OGRVRTLayer name=\"pts\"><SrcDataSource>" +
                           (dir / "pts.csv").string() +
                           "</SrcDataSource><GeometryType>wkbPoint</GeometryType><GeometryField "
                           "encoding=\"PointFromColumns\" x=\"x\" y=\"y\" z=\"z\"/></OGRVRTLayer>"
                           "</OGRVRTDataSource>");
  return dir.write("pts.xyz", text.str());
}

int shell(const std::string& command) {
  return std::system(command.c_str());
}

std::string shellOutput(const std::string& command) {
  std::string out;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
    pclose(pipe);
  }
  return out;
}

// gdal_grid on the grid [0, 10] x [0, 8] of 20 x 16 cells (north-up: -tye from the top).
RasterImage gdalGrid(const TempDir& dir, const std::string& algorithm, const std::string& name) {
  const auto out = dir / (name + ".tif");
  const std::string command = "gdal_grid -q -a " + algorithm +
                              " -txe 0 10 -tye 8 0 -outsize 20 16 -ot Float32 -l pts " +
                              quoted((dir / "pts.vrt").string()) + " " + quoted(out.string());
  EXPECT_EQ(shell(command), 0) << command;
  return readRaster(out);
}

RasterImage parallaxRaster(const TempDir& dir, const std::filesystem::path& input,
                           const std::string& options, const std::string& name) {
  const auto out = dir / (name + ".tif");
  const auto r =
      runParallax(dir, "raster " + quoted(input.string()) + " -o " + quoted(out.string()) +
                           " --resolution 0.5 --bounds 0,0,10,8 -q " + options);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return readRaster(out);
}

// Points near the centres of the cells of 0.5 (within 0.2 < R / 2): there, the cell rule (a
// square) and gdal_grid's search circle of radius R / 2 about the centre take the same points.
// A point between the circle and the square's corner would count for Parallax only: the two
// rules differ there, and only there. One cell in seven stays empty.
std::vector<Xyz> pointsNearCentres() {
  std::mt19937 random(27);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Xyz> points;
  for (int row = 0; row < 16; ++row) {
    for (int column = 0; column < 20; ++column) {
      if ((row * 20 + column) % 7 == 3) continue;
      const int n = 1 + (row + column) % 5;
      for (int k = 0; k < n; ++k) {
        const double angle = 2 * M_PI * unit(random), d = 0.2 * unit(random);
        points.push_back({round3(0.25 + 0.5 * column + d * std::cos(angle)),
                          round3(0.25 + 0.5 * row + d * std::sin(angle)),
                          round3(100 + 10 * unit(random))});
      }
    }
  }
  return points;
}

void expectSameCells(const RasterImage& ours, const RasterImage& gdal, double tolerance,
                     const std::string& what) {
  ASSERT_TRUE(sameGrid(ours.grid, gdal.grid)) << what;
  std::size_t with_value = 0;
  for (std::size_t i = 0; i < ours.values.size(); ++i) {
    const bool ours_empty = ours.values[i] == ours.nodata;
    const bool gdal_empty = gdal.values[i] == gdal.nodata;
    ASSERT_EQ(ours_empty, gdal_empty) << what << " cell " << i;
    if (ours_empty) continue;
    ++with_value;
    EXPECT_NEAR(ours.values[i], gdal.values[i], tolerance * std::abs(gdal.values[i]))
        << what << " cell " << i;
  }
  EXPECT_GT(with_value, ours.values.size() / 2) << what;
}

TEST(RasterCli, MinMaxMeanCountEqualGdalGridWhereTheCellRulesAgree) {
  TempDir dir;
  const auto input = writePoints(dir, pointsNearCentres());
  const std::string circle = ":radius1=0.25:radius2=0.25:nodata=-9999";
  // Float32 of the same numbers: equal to a few ulps (the text reader's quantization).
  expectSameCells(parallaxRaster(dir, input, "--value min", "min"),
                  gdalGrid(dir, "minimum" + circle, "gmin"), 1e-7, "min");
  expectSameCells(parallaxRaster(dir, input, "--value max", "max"),
                  gdalGrid(dir, "maximum" + circle, "gmax"), 1e-7, "max");
  expectSameCells(parallaxRaster(dir, input, "--value mean", "mean"),
                  gdalGrid(dir, "average" + circle, "gmean"), 1e-6, "mean");
  // Counts: 0 in empty cells for both (gdal_grid's min_points is 0).
  const RasterImage count = parallaxRaster(dir, input, "--value count", "count");
  expectSameCells(count, gdalGrid(dir, "count" + circle, "gcount"), 0.0, "count");
  const RasterImage density = parallaxRaster(dir, input, "--value density", "density");
  for (std::size_t i = 0; i < count.values.size(); ++i) {
    ASSERT_EQ(density.values[i], count.values[i] / 0.25f) << i;
  }
}

TEST(RasterCli, IdwEqualsGdalGridInvdistWithTheSameRadius) {
  TempDir dir;
  std::mt19937 random(2027);
  std::uniform_real_distribution<double> x(0.0, 10.0), y(0.0, 8.0), z(50.0, 60.0);
  std::vector<Xyz> points;
  for (int i = 0; i < 400; ++i)
    points.push_back({round3(x(random)), round3(y(random)), round3(z(random))});
  const auto input = writePoints(dir, points);
  // Radius 0.5 (the default: one resolution); some cells see no point and stay nodata.
  expectSameCells(
      parallaxRaster(dir, input, "--value idw", "idw"),
      gdalGrid(dir, "invdist:power=2:smoothing=0:radius1=0.5:radius2=0.5:nodata=-9999", "gidw"),
      1e-6, "idw");
  expectSameCells(
      parallaxRaster(dir, input, "--value idw --idw-radius 0.8", "idw8"),
      gdalGrid(dir, "invdist:power=2:smoothing=0:radius1=0.8:radius2=0.8:nodata=-9999", "gidw8"),
      1e-6, "idw radius 0.8");
}

TEST(RasterCli, GdalinfoReadsTheCrsNodataTilesCompressionAndValues) {
  TempDir dir;
  const auto las = test::testDataFile("laz/point10.las");
  const auto out = dir / "dsm.tif";
  const auto r = runParallax(dir, "raster " + quoted(las.string()) + " -o " + quoted(out.string()) +
                                      " --resolution 2 --value max");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("EPSG:26910"), std::string::npos) << r.err;
  // Nothing but the output is left beside it (the temporary file was renamed).
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"dsm.tif", "stderr.txt", "stdout.txt"}));

  const auto info = nlohmann::json::parse(
      shellOutput("gdalinfo -stats -json " + quoted(out.string()) + " 2>/dev/null"));
  const PointFileHeader header = readPointFileHeader(las);
  const RasterGrid grid = alignedGrid(header.bounds->min[0], header.bounds->min[1],
                                      header.bounds->max[0], header.bounds->max[1], 2.0);
  EXPECT_EQ(info["size"], (nlohmann::json{grid.columns, grid.rows}));
  const auto transform = grid.geoTransform();
  for (int i = 0; i < 6; ++i) EXPECT_EQ(info["geoTransform"][i].get<double>(), transform[i]) << i;
  EXPECT_NE(info["coordinateSystem"]["wkt"].get<std::string>().find("ID[\"EPSG\",26910]"),
            std::string::npos);
  EXPECT_EQ(info["metadata"]["IMAGE_STRUCTURE"]["COMPRESSION"], "DEFLATE");
  const auto& band = info["bands"][0];
  EXPECT_EQ(band["type"], "Float32");
  EXPECT_EQ(band["block"], (nlohmann::json{256, 256}));
  EXPECT_EQ(band["noDataValue"].get<double>(), -9999.0);
  // The highest cell is the highest point; the lowest cell's max is at least the lowest point.
  const PointCloud cloud = readPointFile(las);
  double min_z = 1e300, max_z = -1e300;
  for (std::size_t i = 0; i < cloud.count; ++i) {
    min_z = std::min(min_z, cloud.worldZ(i));
    max_z = std::max(max_z, cloud.worldZ(i));
  }
  // (gdalinfo's JSON prints the statistics to 0.01 or so.)
  EXPECT_NEAR(band["maximum"].get<double>(), max_z, 0.01);
  EXPECT_GE(band["minimum"].get<double>(), min_z - 0.01);
}

TEST(RasterCli, TheWktOfACopcFileAndACanopyHeightModelByMinus) {
  TempDir dir;
  const auto copc = test::testDataFile("laz/simple.copc.laz");
  auto r = runParallax(dir, "raster " + quoted(copc.string()) + " -o " +
                                quoted((dir / "i.tif").string()) +
                                " --resolution 5 --value intensity -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(readRaster(dir / "i.tif").wkt.find("NAD83 / Oregon LCC (m)"), std::string::npos);

  // CHM = DSM (first returns, max) - DTM (class 2, min), cell by cell, nodata where either is.
  const auto las = test::testDataFile("laz/1815.las");
  const std::string base = "raster " + quoted(las.string()) + " --resolution 4 -q -o ";
  r = runParallax(dir, base + quoted((dir / "dtm.tif").string()) + " --classes 2 --value min");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = runParallax(dir, base + quoted((dir / "dsm.tif").string()) + " --returns first --value max");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = runParallax(dir, base + quoted((dir / "chm.tif").string()) +
                           " --returns first --value max --minus " +
                           quoted((dir / "dtm.tif").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const RasterImage dtm = readRaster(dir / "dtm.tif"), dsm = readRaster(dir / "dsm.tif");
  const RasterImage chm = readRaster(dir / "chm.tif");
  std::size_t both = 0;
  for (std::size_t i = 0; i < chm.values.size(); ++i) {
    if (dtm.values[i] == dtm.nodata || dsm.values[i] == dsm.nodata) {
      ASSERT_EQ(chm.values[i], chm.nodata) << i;
    } else {
      ASSERT_EQ(chm.values[i], dsm.values[i] - dtm.values[i]) << i;
      ++both;
    }
  }
  EXPECT_GT(both, 10u);
  // Another grid cannot be subtracted.
  r = runParallax(dir, "raster " + quoted(las.string()) + " --resolution 2 -o " +
                           quoted((dir / "x.tif").string()) + " --minus " +
                           quoted((dir / "dtm.tif").string()));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--minus"), std::string::npos) << r.err;
}

TEST(RasterCli, BandsOfRowsWithinMemoryGiveTheSameRaster) {
  TempDir dir;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> xy(0.0, 600.0), z(0.0, 30.0);
  std::ostringstream text;
  text.precision(3);
  text << std::fixed;
  for (int i = 0; i < 30000; ++i)
    text << xy(random) << ' ' << xy(random) << ' ' << z(random) << '\n';
  const auto input = dir.write("big.xyz", text.str());
  // 600 x 600 cells of 4 + 4 bytes: 2.7 MB; --memory 1, less an eighth for GDAL's block cache,
  // makes bands of 191 rows, four reads.
  const auto whole = runParallax(dir, "raster " + quoted(input.string()) + " -o " +
                                          quoted((dir / "whole.tif").string()) +
                                          " --resolution 1 --bounds 0,0,600,600 --value max");
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_NE(whole.err.find("1 pass(es)"), std::string::npos) << whole.err;
  const auto banded = runParallax(dir, "raster " + quoted(input.string()) + " -o " +
                                           quoted((dir / "banded.tif").string()) +
                                           " --resolution 1 --bounds 0,0,600,600 --value max "
                                           "--memory 1");
  ASSERT_EQ(banded.exit_code, 0) << banded.err;
  EXPECT_NE(banded.err.find("4 pass(es)"), std::string::npos) << banded.err;
  EXPECT_EQ(readRaster(dir / "whole.tif").values, readRaster(dir / "banded.tif").values);
  // --fill needs the grid whole: refused within 1 MB, naming --memory.
  const auto fill = runParallax(dir, "raster " + quoted(input.string()) + " -o " +
                                         quoted((dir / "fill.tif").string()) +
                                         " --resolution 1 --fill --memory 1");
  EXPECT_EQ(fill.exit_code, 1);
  EXPECT_NE(fill.err.find("--memory"), std::string::npos) << fill.err;
}

std::vector<std::uint8_t> readBytes(const std::filesystem::path& path, int& columns, int& rows) {
  GDALAllRegister();
  GDALDatasetH dataset = GDALOpen(path.c_str(), GA_ReadOnly);
  EXPECT_NE(dataset, nullptr) << path;
  if (!dataset) return {};
  columns = GDALGetRasterXSize(dataset);
  rows = GDALGetRasterYSize(dataset);
  std::vector<std::uint8_t> bytes(std::size_t(columns) * std::size_t(rows));
  EXPECT_EQ(GDALRasterIO(GDALGetRasterBand(dataset, 1), GF_Read, 0, 0, columns, rows, bytes.data(),
                         columns, rows, GDT_Byte, 0, 0),
            CE_None);
  GDALClose(dataset);
  return bytes;
}

TEST(RasterCli, HillshadeEqualsGdaldemOnTheSameRaster) {
  TempDir dir;
  // A smooth hill with a slope, one point at each cell's centre, a gap of a few cells.
  std::vector<Xyz> points;
  for (int row = 0; row < 16; ++row) {
    for (int column = 0; column < 20; ++column) {
      if (row == 8 && column >= 5 && column < 8) continue;
      const double x = 0.25 + 0.5 * column, y = 0.25 + 0.5 * row;
      points.push_back({x, y, round3(3 * std::sin(x / 2) * std::cos(y / 3) + 0.4 * x)});
    }
  }
  const auto input = writePoints(dir, points);
  const auto out = dir / "hill.tif";
  const auto r =
      runParallax(dir, "raster " + quoted(input.string()) + " -o " + quoted(out.string()) +
                           " --resolution 0.5 --bounds 0,0,10,8 --value mean --hillshade");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(std::filesystem::exists(dir / "hill_hillshade.png"));
  ASSERT_EQ(shell("gdaldem hillshade -q " + quoted(out.string()) + " " +
                  quoted((dir / "gdaldem.tif").string())),
            0);
  int columns = 0, rows = 0, gc = 0, gr = 0;
  const auto ours = readBytes(dir / "hill_hillshade.png", columns, rows);
  const auto gdal = readBytes(dir / "gdaldem.tif", gc, gr);
  ASSERT_EQ(columns, gc);
  ASSERT_EQ(rows, gr);
  std::size_t equal = 0, lit = 0;
  for (std::size_t i = 0; i < ours.size(); ++i) {
    // Same pixels without a value (border, next to the gap); shades equal but for GDAL's
    // approximate reciprocal square root (hillshade.h): one grey level at most.
    ASSERT_EQ(ours[i] == 0, gdal[i] == 0) << i;
    EXPECT_LE(std::abs(int(ours[i]) - int(gdal[i])), 1) << i;
    equal += ours[i] == gdal[i];
    lit += ours[i] != 0;
  }
  EXPECT_GT(lit, 200u);
  EXPECT_GE(equal * 100, ours.size() * 95);
}

TEST(RasterCli, BadOptionsNameTheOptionAndWriteNothing) {
  TempDir dir;
  const auto input = writePoints(dir, pointsNearCentres());
  const std::string base = "raster " + quoted(input.string()) + " -o ";
  const std::string out = quoted((dir / "o.tif").string());
  auto r = runParallax(dir, base + out + " --resolution 0");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--resolution: expected a positive number"), std::string::npos) << r.err;
  r = runParallax(dir, base + out + " --resolution -2");
  EXPECT_NE(r.err.find("--resolution"), std::string::npos) << r.err;
  r = runParallax(dir, base + out + " --resolution 1 --value median");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--value: expected one of min|max|mean|idw|count|density|intensity, "
                       "found 'median'"),
            std::string::npos)
      << r.err;
  r = runParallax(dir, base + quoted((dir / "missing" / "o.tif").string()) + " --resolution 1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("-o "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
  r = runParallax(dir, base + out + " --resolution 1 --bounds 5,0,1,8");
  EXPECT_NE(r.err.find("--bounds"), std::string::npos) << r.err;
  r = runParallax(dir, base + out + " --resolution 1 --value intensity");
  EXPECT_NE(r.err.find("no intensity"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "o.tif"));
  r = runParallax(
      dir, "raster " + quoted((dir / "none.las").string()) + " -o " + out + " --resolution 1");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  // The input as the output (through another spelling of its path): refused, the input kept; it
  // was replaced by the GeoTIFF.
  const std::uintmax_t input_size = std::filesystem::file_size(input);
  const std::filesystem::path again = dir / "." / input.filename();
  r = runParallax(
      dir, base.substr(0, base.size() - 4) + " -o " + quoted(again.string()) + " --resolution 1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("-o " + again.string() +
                       ": is the input point file, which the GeoTIFF would replace"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(std::filesystem::file_size(input), input_size);
  // A grid under 2^31 - 1 cells a side but over a GeoTIFF's tile index: the option named, exit 1
  // (it was GDAL's "File too large regarding tile size").
  r = runParallax(dir, base + out + " --resolution 1e-9 --bounds 0,0,1,1");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--resolution 1e-09: the grid of 1000000000 x 1000000000 cells"),
            std::string::npos)
      << r.err;
}

TEST(VolumeCli, JsonResultAndPolygonErrorsNamingTheFile) {
  TempDir dir;
  // A box 2 x 3 x 1.5 on flat ground at z 10, one point a cell of 0.25 at its centre.
  std::vector<Xyz> points;
  for (int row = 0; row < 40; ++row) {
    for (int column = 0; column < 40; ++column) {
      const double x = 0.125 + 0.25 * column, y = 0.125 + 0.25 * row;
      const bool in_box = x > 3 && x < 5 && y > 3 && y < 6;
      points.push_back({x, y, in_box ? 11.5 : 10.0});
    }
  }
  const auto input = writePoints(dir, points);
  const auto polygon = dir.write(
      "p.geojson",
      R"({"type": "Polygon", "coordinates": [[[1, 1], [9, 1], [9, 9], [1, 9], [1, 1]]]})");
  auto r = runParallax(
      dir, "volume " + quoted(input.string()) + " --polygon " + quoted(polygon.string()) +
               " --resolution 0.25 --json --raster-out " + quoted((dir / "d.tif").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto json = nlohmann::json::parse(r.out);
  EXPECT_NEAR(json["cut"].get<double>(), 9.0, 1e-6);
  EXPECT_NEAR(json["fill"].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(json["net"].get<double>(), 9.0, 1e-6);
  EXPECT_NEAR(json["area"].get<double>(), 64.0, 1e-9);
  EXPECT_EQ(json["base"], "plane");
  EXPECT_NEAR(json["plane"][2].get<double>(), 10.0, 1e-9);
  EXPECT_TRUE(std::filesystem::exists(dir / "d.tif"));

  const auto bad = dir.write("bad.geojson", R"({"type": "Polygon", "coordinates": [[[1, 1]]]})");
  r = runParallax(dir, "volume " + quoted(input.string()) + " --polygon " + quoted(bad.string()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(bad.string()), std::string::npos) << r.err;
  r = runParallax(dir, "volume " + quoted(input.string()) + " --polygon " +
                           quoted((dir / "none.geojson").string()));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("none.geojson"), std::string::npos) << r.err;
  r = runParallax(dir, "volume " + quoted(input.string()) + " --polygon " +
                           quoted(polygon.string()) + " --base nowhere.tif");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("--base"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace parallax
