// The coordinate reference system travels: from a LAS file's projection records into the octree's
// metadata.json "projection" (the WKT as written, or the best name of its GeoTIFF keys), into
// LAS outputs (the records copied), and into `info` of the octree.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "core/error.h"
#include "io/coordinate_system.h"
#include "io/las_header.h"
#include "io/test_las_builder.h"
#include "lod/potree_converter.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

// NAD83(HARN) / Lambert, as a county's LAS 1.4 tiles carry it (abridged, as written).
const std::string kWkt =
    "PROJCS[\"NAD83(HARN) / Oregon GIC Lambert (ft)\",GEOGCS[\"NAD83(HARN)\",DATUM[\"NAD83_High_"
    "Accuracy_Reference_Network\",SPHEROID[\"GRS 1980\",6378137,298.257222101]],PRIMEM["
    "\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]],PROJECTION[\"Lambert_Conformal_Conic_"
    "2SP\"],PARAMETER[\"standard_parallel_1\",43],PARAMETER[\"standard_parallel_2\",45.5],"
    "UNIT[\"foot\",0.3048],AUTHORITY[\"EPSG\",\"2994\"]]";

std::string geoKeys(std::initializer_list<std::uint16_t> keys) {
  std::string bytes;
  const std::uint16_t count = std::uint16_t(keys.size() / 4);
  for (std::uint16_t v : {std::uint16_t(1), std::uint16_t(1), std::uint16_t(0), count}) {
    bytes.append(reinterpret_cast<const char*>(&v), 2);
  }
  for (std::uint16_t v : keys) bytes.append(reinterpret_cast<const char*>(&v), 2);
  return bytes;
}

LasTestFile lasTile(int seed) {
  LasTestFile file{.minor = 4, .format = 6};
  file.scale[0] = file.scale[1] = file.scale[2] = 0.01;
  for (int i = 0; i < 3000; ++i) {
    LasTestPoint p;
    p.x = (i * 7919 + seed) % 100000, p.y = (i * 104729 + seed) % 100000, p.z = i % 500;
    file.points.push_back(p);
  }
  return file;
}

LasTestFile wktTile() {
  LasTestFile file = lasTile(1);
  file.global_encoding = 16;
  file.vlrs.push_back({"LASF_Projection", 2112, kWkt + std::string(1, '\0')});
  return file;
}

LasTestFile geoTiffTile(std::uint16_t projected, int seed = 1) {
  LasTestFile file = lasTile(seed);
  file.minor = 2;
  file.format = 1;
  file.vlrs.push_back(
      {"LASF_Projection", 34735, geoKeys({3072, 0, 1, projected, 4096, 0, 1, 5703})});
  file.vlrs.push_back({"LASF_Projection", 34737, std::string("NAD83 / UTM zone 15N|\0", 22)});
  return file;
}

nlohmann::json metadataOf(const std::filesystem::path& dir) {
  return nlohmann::json::parse(readText(dir / "metadata.json"));
}

TEST(CrsTravels, PotreeProjectionFromGeoTiffKeys) {
  LasCrs crs;
  crs.projected_epsg = 26915;
  EXPECT_EQ(potreeProjection(crs), "+proj=utm +zone=15 +datum=NAD83 +units=m +no_defs");
  crs.projected_epsg = 32633;
  EXPECT_EQ(potreeProjection(crs), "+proj=utm +zone=33 +datum=WGS84 +units=m +no_defs");
  crs.projected_epsg = 32733;
  EXPECT_EQ(potreeProjection(crs), "+proj=utm +zone=33 +south +datum=WGS84 +units=m +no_defs");
  crs.projected_epsg = 26710;
  EXPECT_EQ(potreeProjection(crs), "+proj=utm +zone=10 +datum=NAD27 +units=m +no_defs");
  crs.projected_epsg = 25832;
  EXPECT_EQ(potreeProjection(crs),
            "+proj=utm +zone=32 +ellps=GRS80 +towgs84=0,0,0,0,0,0,0 +units=m +no_defs");
  crs.projected_epsg = 2056;  // Swiss LV95: no fixed proj4 string here
  EXPECT_EQ(potreeProjection(crs), "EPSG:2056");
  crs.projected_epsg = 32767;  // user-defined: no name, not even its geographic base's
  crs.geographic_epsg = 4269;
  EXPECT_EQ(potreeProjection(crs), "");
  crs.projected_epsg.reset();
  EXPECT_EQ(potreeProjection(crs), "+proj=longlat +datum=NAD83 +no_defs");
  crs.geographic_epsg = 4326;
  EXPECT_EQ(potreeProjection(crs), "+proj=longlat +datum=WGS84 +no_defs");
  crs.wkt = kWkt;  // a WKT wins, as written
  EXPECT_EQ(potreeProjection(crs), kWkt);
  EXPECT_EQ(potreeProjection(LasCrs{}), "");
}

TEST(CrsTravels, WktGoesIntoTheOctreeAsWritten) {
  TempDir dir;
  const auto in = dir.write("tile.las", makeLas(wktTile()));
  const PotreeConvertResult result = convertToPotree({{in, {}}}, dir / "octree");
  EXPECT_EQ(result.crs.summary(), "NAD83(HARN) / Oregon GIC Lambert (ft) (WKT)");
  EXPECT_EQ(metadataOf(dir / "octree")["projection"], kWkt);
}

TEST(CrsTravels, GeoTiffKeysGoInAsTheirProj4String) {
  TempDir dir;
  const auto in = dir.write("tile.las", makeLas(geoTiffTile(26915)));
  convertToPotree({{in, {}}}, dir / "octree");
  EXPECT_EQ(metadataOf(dir / "octree")["projection"],
            "+proj=utm +zone=15 +datum=NAD83 +units=m +no_defs");
}

TEST(CrsTravels, MergedInputsMustAgree) {
  TempDir dir;
  const auto a = dir.write("a.las", makeLas(geoTiffTile(26915, 1)));
  const auto same = dir.write("same.las", makeLas(geoTiffTile(26915, 2)));
  const auto other = dir.write("other.las", makeLas(geoTiffTile(26916, 3)));
  const auto none = dir.write("none.las", makeLas(lasTile(4)));
  // The same CRS, or none stated: merged, the CRS kept.
  const PotreeConvertResult result =
      convertToPotree({{none, {}}, {a, {}}, {same, {}}}, dir / "merged");
  EXPECT_EQ(result.points, 9000u);
  EXPECT_EQ(metadataOf(dir / "merged")["projection"],
            "+proj=utm +zone=15 +datum=NAD83 +units=m +no_defs");
  try {
    convertToPotree({{a, {}}, {other, {}}}, dir / "mixed");
    FAIL() << "merged two coordinate systems";
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().file, other.string());
    EXPECT_EQ(e.info().found, "EPSG:26916 + EPSG:5703 \"NAD83 / UTM zone 15N|\" (GeoTIFF keys)");
    EXPECT_NE(e.info().expected.find(a.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "mixed"));
}

TEST(CrsTravels, ConvertAndInfoThroughTheCommandLine) {
  TempDir dir;
  const auto in = dir.write("tile.las", makeLas(wktTile()));
  RunResult run = runParallax(
      dir, "convert " + quoted(in.string()) + " -o " + quoted((dir / "octree/").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("coordinate reference system NAD83(HARN) / Oregon GIC Lambert (ft) "
                         "(WKT): written as metadata.json \"projection\""),
            std::string::npos)
      << run.err;
  run = runParallax(dir, "info " + quoted((dir / "octree").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("\nprojection    NAD83(HARN) / Oregon GIC Lambert (ft) (WKT)\n"),
            std::string::npos)
      << run.out;
  run = runParallax(dir, "info --json " + quoted((dir / "octree").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(nlohmann::json::parse(run.out)["format_details"]["projection"], kWkt);
}

TEST(CrsTravels, LasOutputsCopyTheRecords) {
  TempDir dir;
  // WKT: copied, and the output is LAS 1.4 with the WKT bit (the only version that has it).
  const auto wkt = dir.write("wkt.las", makeLas(wktTile()));
  RunResult run = runParallax(
      dir, "convert -q " + quoted(wkt.string()) + " -o " + quoted((dir / "wkt_out.las").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  LasHeader out = readLasHeader(dir / "wkt_out.las");
  EXPECT_EQ(out.crs.wkt, kWkt);
  EXPECT_EQ(out.versionString(), "1.4");
  EXPECT_EQ(out.global_encoding & 16, 16);
  // GeoTIFF keys: every record byte for byte.
  const auto geo = dir.write("geo.las", makeLas(geoTiffTile(26915)));
  run = runParallax(
      dir, "convert -q " + quoted(geo.string()) + " -o " + quoted((dir / "geo_out.las").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const CoordinateSystem source = coordinateSystemOf(readLasHeader(geo));
  const CoordinateSystem copied = coordinateSystemOf(readLasHeader(dir / "geo_out.las"));
  ASSERT_EQ(copied.records.size(), 2u);
  EXPECT_TRUE(copied.sameAs(source));
  EXPECT_EQ(copied.description.projected_epsg, 26915);
  EXPECT_EQ(copied.description.vertical_epsg, 5703);
}

}  // namespace
}  // namespace parallax::test
