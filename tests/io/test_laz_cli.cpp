// LAZ through the command line, as a user meets it: `info` describes the compression, `convert`
// reads LAZ into every format and writes it from every format, and an octree built from a LAZ
// file holds the same points as one built from its LAS twin; a damaged file is an error that
// names the chunk.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "io/las_reader.h"
#include "io/laz_reader.h"
#include "io/laz_test_files.h"
#include "io/ply_reader.h"
#include "support/run_parallax.h"

namespace parallax {
namespace {

using test::lazData;
using test::quoted;

TEST(LazCli, InfoDescribesTheCompression) {
  test::TempDir dir;
  const auto run =
      test::runParallax(dir, "info --json " + quoted(lazData("extrabytes.laz").string()));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto info = nlohmann::json::parse(run.out);
  EXPECT_EQ(info["format"], "laz");
  EXPECT_EQ(info["points"], 1065);
  const auto& laz = info["format_details"]["laz"];
  EXPECT_EQ(laz["compressor"], 2);
  EXPECT_EQ(laz["chunk_size"], 50000);
  EXPECT_EQ(laz["chunks"], 1);
  EXPECT_EQ(laz["items"][3], "BYTE v2 (27 bytes)");
  EXPECT_EQ(info["format_details"]["point_format"], 3);
  const auto text = test::runParallax(dir, "info " + quoted(lazData("ellipsoid.laz").string()));
  EXPECT_NE(
      text.out.find("LAZ point-wise chunked (compressor 2), chunks of 50000 points, 2 chunks"),
      std::string::npos)
      << text.out;
}

TEST(LazCli, ConvertsToAndFromEveryFormat) {
  test::TempDir dir;
  const std::string source = quoted(lazData("point-color-time.las.laz").string());
  for (const char* out : {"a.ply", "a.las", "a.xyz", "a.laz"}) {
    const auto run =
        test::runParallax(dir, "convert " + source + " -o " + quoted((dir / out).string()) + " -q");
    ASSERT_EQ(run.exit_code, 0) << out << ": " << run.err;
  }
  // PLY -> LAZ (small chunks) -> PLY gives the PLY back.
  ASSERT_EQ(test::runParallax(dir, "convert " + quoted((dir / "a.ply").string()) + " -o " +
                                       quoted((dir / "b.laz").string()) + " --laz-chunk 100 -q")
                .exit_code,
            0);
  ASSERT_EQ(test::runParallax(dir, "convert " + quoted((dir / "b.laz").string()) + " -o " +
                                       quoted((dir / "b.ply").string()) + " -q")
                .exit_code,
            0);
  EXPECT_EQ(summarizeLaz(dir / "b.laz").chunks, 11u);
  const PointCloud a = readPly(dir / "a.ply"), b = readPly(dir / "b.ply");
  ASSERT_EQ(a.count, 1065u);
  ASSERT_EQ(b.count, a.count);
  for (std::size_t i = 0; i < a.count; ++i) {
    ASSERT_EQ(b.worldX(i), a.worldX(i));
    ASSERT_EQ(b.worldZ(i), a.worldZ(i));
    ASSERT_EQ(b.colors[i], a.colors[i]);
  }
  // LAZ -> LAZ keeps the CRS records of the source.
  EXPECT_EQ(readLasHeader(dir / "a.laz").crs.summary(),
            readLasHeader(lazData("point-color-time.las.laz")).crs.summary());
}

TEST(LazCli, OctreeFromLazEqualsOctreeFromLas) {
  test::TempDir dir;
  for (const char* name : {"point-time.las", "point-time.las.laz"}) {
    const auto run = test::runParallax(dir, "convert " + quoted(lazData(name).string()) + " -o " +
                                                quoted((dir / name).string() + ".potree/") + " -q");
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }
  const std::string las = test::fileBytes(dir / "point-time.las.potree" / "octree.bin");
  const std::string laz = test::fileBytes(dir / "point-time.las.laz.potree" / "octree.bin");
  EXPECT_FALSE(las.empty());
  EXPECT_EQ(las, laz);
}

TEST(LazCli, DamagedFileIsAnErrorNamingTheChunk) {
  test::TempDir dir;
  std::string bytes = test::fileBytes(lazData("ellipsoid.laz"));
  // A run of bytes in the middle of the second chunk (bytes 127 279 to 261 709).
  for (std::size_t i = 200000; i < 200100; ++i) bytes[i] = char(0xA5);
  const auto path = dir.write("bad.laz", bytes);
  const auto run = test::runParallax(dir, "info " + quoted(path.string()));
  EXPECT_EQ(run.exit_code, 2) << run.err;  // input errors
  EXPECT_NE(run.err.find("LAZ chunk 2 of 2 (points 50000-99999)"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("byte offset 127279"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("first point affected: 50000"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace parallax
