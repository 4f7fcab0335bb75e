// COPC on the command line, end to end (the built `parallax`): convert to and from COPC, info,
// and render: a cloud written as COPC and as a Potree directory gives the same picture.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "io/las_header.h"
#include "io/las_writer.h"
#include "io/point_file.h"
#include "lod/copc_reader.h"
#include "lod/copc_test_files.h"
#include "lod/lod_test_clouds.h"
#include "render/image_file.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

constexpr const char* kWkt =
    "PROJCS[\"WGS 84 / UTM zone 33N\",GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\","
    "6378137,298.257223563]],PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]],"
    "PROJECTION[\"Transverse_Mercator\"],PARAMETER[\"central_meridian\",15],UNIT[\"metre\",1]]";

// A LAS 1.4 file of a surface cloud with a WKT CRS.
void writeLasWithWkt(const std::filesystem::path& path, std::uint64_t points) {
  LasWriteOptions options;
  options.minor_version = 4;
  LasVlr wkt{.user_id = "LASF_Projection", .record_id = 2112, .description = "WKT"};
  const std::string text = kWkt;
  wkt.data.resize(text.size() + 1);
  std::memcpy(wkt.data.data(), text.data(), text.size());
  options.vlrs.push_back(wkt);
  writeLas(makeSurfaceCloud(points, 4), path, options);
}

TEST(CopcCli, ConvertsToCopcWithItsCrsAndInfoDescribesIt) {
  TempDir dir;
  writeLasWithWkt(dir / "in.las", 30000);
  const RunResult run =
      runParallax(dir, "convert " + quoted((dir / "in.las").string()) + " -o " +
                           quoted((dir / "out.copc.laz").string()) + " --memory 64");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("COPC 1.0, point format 7, 30000 points"), std::string::npos) << run.err;
  const LasHeader header = readLasHeader(dir / "out.copc.laz");
  EXPECT_EQ(header.crs.wkt, kWkt);
  EXPECT_EQ(header.vlrs[0].user_id, "copc");  // the info VLR first

  const RunResult info = runParallax(dir, "info --json " + quoted((dir / "out.copc.laz").string()));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const auto json = nlohmann::json::parse(info.out);
  EXPECT_EQ(json["format"], "copc");
  EXPECT_EQ(json["points"], 30000);
  EXPECT_EQ(json["format_details"]["point_format"], 7);
  EXPECT_EQ(json["format_details"]["crs"], "WGS 84 / UTM zone 33N (WKT)");
  std::uint64_t per_level = 0;
  for (const auto& level : json["format_details"]["hierarchy"]["levels"]) {
    per_level += level["points"].get<std::uint64_t>();
  }
  EXPECT_EQ(per_level, 30000u);
  const RunResult text = runParallax(dir, "info " + quoted((dir / "out.copc.laz").string()));
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("COPC 1.0: LAS 1.4, point format 7"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("level  0"), std::string::npos) << text.out;
}

TEST(CopcCli, GeoTiffKeysCannotBeCarriedAndSaySo) {
  TempDir dir;
  // Format 0 with a GeoTIFF key directory (EPSG:32633) and no WKT.
  LasWriteOptions options;
  LasVlr keys{.user_id = "LASF_Projection", .record_id = 34735, .description = "GeoTIFF"};
  const std::uint16_t words[] = {1, 1, 0, 1, 3072, 0, 1, 32633};
  keys.data.resize(sizeof words);
  std::memcpy(keys.data.data(), words, sizeof words);
  options.vlrs.push_back(keys);
  writeLas(makeSurfaceCloud(2000, 4), dir / "keys.las", options);
  const RunResult run = runParallax(dir, "convert " + quoted((dir / "keys.las").string()) + " -o " +
                                             quoted((dir / "keys.copc.laz").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("not carried over: the CRS of"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("EPSG:32633"), std::string::npos) << run.err;
  EXPECT_TRUE(readLasHeader(dir / "keys.copc.laz").crs.empty());
}

TEST(CopcCli, BetweenTheOctreeFormatsNodeByNode) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(30000, 6), dir / "in.ply");
  ASSERT_EQ(runParallax(dir, "convert -q " + quoted((dir / "in.ply").string()) + " -o " +
                                 quoted((dir / "a.copc.laz").string()))
                .exit_code,
            0);
  const RunResult to_potree = runParallax(dir, "convert " + quoted((dir / "a.copc.laz").string()) +
                                                   " -o " + quoted((dir / "tree").string()));
  ASSERT_EQ(to_potree.exit_code, 0) << to_potree.err;
  EXPECT_NE(to_potree.err.find("re-encoded node by node"), std::string::npos) << to_potree.err;
  const RunResult back = runParallax(dir, "convert " + quoted((dir / "tree").string()) + " -o " +
                                              quoted((dir / "b.copc.laz").string()));
  ASSERT_EQ(back.exit_code, 0) << back.err;
  EXPECT_NE(back.err.find("re-encoded node by node"), std::string::npos) << back.err;
  // The same file again (its creation date and the cube's rounding aside).
  auto bytes = [&](const char* name) {
    std::vector<std::byte> b = readBytes(dir / name);
    std::fill_n(b.begin() + 90, 4, std::byte{0});
    std::fill_n(b.begin() + 429, 32, std::byte{0});
    return b;
  };
  EXPECT_EQ(bytes("a.copc.laz"), bytes("b.copc.laz"));
  // --spacing asks for another tree: rebuilt.
  const RunResult rebuilt =
      runParallax(dir, "convert " + quoted((dir / "tree").string()) + " -o " +
                           quoted((dir / "c.copc.laz").string()) + " --spacing 2");
  ASSERT_EQ(rebuilt.exit_code, 0) << rebuilt.err;
  EXPECT_EQ(rebuilt.err.find("node by node"), std::string::npos) << rebuilt.err;
  auto c = openCopc(dir / "c.copc.laz");
  EXPECT_EQ(c->info().spacing, 2.0);
  EXPECT_EQ(c->info().point_count, 30000u);
}

TEST(CopcCli, RenderOfCopcAndPotreeGivesTheSamePicture) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(60000, 8), dir / "in.ply");
  const std::string in = quoted((dir / "in.ply").string());
  ASSERT_EQ(runParallax(
                dir, "convert -q " + in + " -o " + quoted((dir / "tree").string()) + " --memory 64")
                .exit_code,
            0);
  ASSERT_EQ(runParallax(dir, "convert -q " + in + " -o " + quoted((dir / "c.copc.laz").string()) +
                                 " --memory 64")
                .exit_code,
            0);
  // A budget below the cloud: level of detail chooses nodes, the same ones for both.
  const std::string options = " --width 160 --height 120 --budget 20000";
  const RunResult potree = runParallax(dir, "render " + quoted((dir / "tree").string()) + " -o " +
                                                quoted((dir / "potree.png").string()) + options);
  ASSERT_EQ(potree.exit_code, 0) << potree.err;
  const RunResult copc =
      runParallax(dir, "render " + quoted((dir / "c.copc.laz").string()) + " -o " +
                           quoted((dir / "copc.png").string()) + options);
  ASSERT_EQ(copc.exit_code, 0) << copc.err;
  const RgbaImage a = readPng(dir / "potree.png");
  const RgbaImage b = readPng(dir / "copc.png");
  ASSERT_EQ(a.width, 160);
  ASSERT_EQ(b.width, 160);
  std::size_t lit = 0, differ = 0;
  for (std::size_t i = 0; i < a.pixels.size(); i += 4) {
    lit += (a.pixels[i] | a.pixels[i + 1] | a.pixels[i + 2]) != 0 ? 1 : 0;
    differ += std::memcmp(&a.pixels[i], &b.pixels[i], 4) != 0 ? 1 : 0;
  }
  EXPECT_GT(lit, 1000u);  // a picture, not an empty frame
  EXPECT_EQ(differ, 0u);  // pixel for pixel
  // Fewer points drawn than the cloud holds ("60000 points (N drawn)"): the budget was at work.
  const std::size_t at = copc.err.find("60000 points (");
  ASSERT_NE(at, std::string::npos) << copc.err;
  const long drawn = std::stol(copc.err.substr(at + 14));
  EXPECT_GT(drawn, 1000);
  EXPECT_LE(drawn, 20000);
  EXPECT_NE(potree.err.find("60000 points (" + std::to_string(drawn) + " drawn)"),
            std::string::npos)
      << potree.err;
}

TEST(CopcCli, ContentNotNameDecidesAndDamageIsNamed) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(3000, 9), dir / "in.ply");
  // A plain LAZ file named .copc.laz is a LAZ file.
  ASSERT_EQ(runParallax(dir, "convert -q " + quoted((dir / "in.ply").string()) + " -o " +
                                 quoted((dir / "plain.laz").string()))
                .exit_code,
            0);
  std::filesystem::rename(dir / "plain.laz", dir / "fake.copc.laz");
  const RunResult fake = runParallax(dir, "info " + quoted((dir / "fake.copc.laz").string()));
  ASSERT_EQ(fake.exit_code, 0) << fake.err;
  EXPECT_EQ(fake.out.find("COPC"), std::string::npos) << fake.out;
  EXPECT_NE(fake.out.find("LAZ"), std::string::npos) << fake.out;
  // A COPC file cut short: an error naming it.
  ASSERT_EQ(runParallax(dir, "convert -q " + quoted((dir / "in.ply").string()) + " -o " +
                                 quoted((dir / "c.copc.laz").string()))
                .exit_code,
            0);
  std::filesystem::resize_file(dir / "c.copc.laz",
                               std::filesystem::file_size(dir / "c.copc.laz") - 100);
  const RunResult cut = runParallax(dir, "render " + quoted((dir / "c.copc.laz").string()) +
                                             " -o " + quoted((dir / "x.png").string()));
  EXPECT_NE(cut.exit_code, 0);
  EXPECT_NE(cut.err.find("c.copc.laz"), std::string::npos) << cut.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
}

}  // namespace
}  // namespace parallax::test
