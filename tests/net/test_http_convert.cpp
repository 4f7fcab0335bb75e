// `parallax convert URL -o FILE` of point files that are no octree, served by nginx: the format
// table opens the URL through core's openByteSource (net's http opener), so a LAZ file and a
// PLY file from a URL convert to exactly what the local file gives, and a URL that cannot be
// read is an error that names it.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/point_file.h"
#include "loopback_servers.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"
#include "support/test_data.h"

namespace parallax {
namespace {

using test::Nginx;
using test::quoted;

std::string fileText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Serves `www` and converts `name` from its URL and from the disk to `output_name`.
struct Converted {
  test::RunResult remote, local;
  std::filesystem::path remote_out, local_out;
};

Converted convertBoth(const test::TempDir& dir, const Nginx& nginx, const std::string& name,
                      const std::string& output_name, const std::string& options = "-q") {
  Converted c;
  c.remote_out = dir / ("remote-" + output_name);
  c.local_out = dir / ("local-" + output_name);
  c.remote = test::runParallax(dir, "convert " + options + " " + quoted(nginx.url(name)) + " -o " +
                                        quoted(c.remote_out.string()));
  c.local =
      test::runParallax(dir, "convert " + options + " " + quoted((dir / "www" / name).string()) +
                                 " -o " + quoted(c.local_out.string()));
  return c;
}

TEST(HttpConvert, ALazFileFromAUrlConvertsToTheLocalFilesLas) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www");
  std::filesystem::copy_file(test::testDataFile("laz/1815.laz"), dir / "www" / "1815.laz");
  ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
  Nginx nginx(dir / "nginx", {.root = dir / "www"});

  const Converted c = convertBoth(dir, nginx, "1815.laz", "1815.las");
  ASSERT_EQ(c.remote.exit_code, 0) << c.remote.err;
  ASSERT_EQ(c.local.exit_code, 0) << c.local.err;
  // Byte for byte: the header fields and VLRs the LAS writer keeps come from the source's
  // header, read from the URL as from the disk.
  const std::string remote = fileText(c.remote_out);
  ASSERT_GT(remote.size(), 227u);
  EXPECT_EQ(remote, fileText(c.local_out));
  // And the points are those of the LAS twin LASzip decompressed.
  const PointCloud got = readPointFile(c.remote_out);
  const PointCloud twin = readPointFile(test::testDataFile("laz/1815.las"));
  ASSERT_EQ(got.count, twin.count);
  ASSERT_GT(got.count, 0u);
  for (std::size_t i = 0; i < got.count; ++i) {
    ASSERT_EQ(got.positions[i], twin.positions[i]) << "point " << i;
  }
  // The file came from nginx: its requests were answered.
  std::uint64_t sent = 0;
  for (const test::AccessLine& line : nginx.settledAccessLog()) sent += line.bytes;
  EXPECT_GE(sent, std::filesystem::file_size(dir / "www" / "1815.laz"));
}

TEST(HttpConvert, ALasFileFromAUrlConvertsByRangesToTheLocalFilesBytes) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www");
  std::filesystem::copy_file(test::testDataFile("laz/1815.las"), dir / "www" / "1815.las");
  ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
  Nginx nginx(dir / "nginx", {.root = dir / "www"});

  // To LAS (header and VLRs carried over) and to LAZ, each byte for byte the local file's.
  for (const char* output : {"1815-copy.las", "1815.laz"}) {
    const Converted c = convertBoth(dir, nginx, "1815.las", output, "-v");
    ASSERT_EQ(c.remote.exit_code, 0) << c.remote.err;
    ASSERT_EQ(c.local.exit_code, 0) << c.local.err;
    const std::string remote = fileText(c.remote_out);
    ASSERT_GT(remote.size(), 227u);
    EXPECT_EQ(remote, fileText(c.local_out)) << output;
    // -v says what the network fetched: requests, bytes, of the file's 35 436 bytes.
    EXPECT_NE(c.remote.err.find("bytes received of a file of 35436 bytes"), std::string::npos)
        << c.remote.err;
    EXPECT_EQ(c.local.err.find("network:"), std::string::npos) << c.local.err;
  }
  // Every answer was a range (206) or "not modified" (304, the cache's), never the whole file.
  const std::vector<test::AccessLine> log = nginx.settledAccessLog();
  ASSERT_FALSE(log.empty());
  for (const test::AccessLine& line : log) {
    EXPECT_TRUE(line.status == 206 || line.status == 304) << line.status << " " << line.range;
  }
}

// A COPC file's URL is read through its octree (the nodes a filter can meet), the local file as
// the LAZ file it also is: both LAS outputs keep the source's header fields and records, the
// WKT CRS among them, byte for byte.
TEST(HttpConvert, ACopcFileFromAUrlConvertsToTheLocalFilesLasBytes) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www");
  std::filesystem::copy_file(test::testDataFile("laz/simple.copc.laz"),
                             dir / "www" / "simple.copc.laz");
  ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
  Nginx nginx(dir / "nginx", {.root = dir / "www"});

  const Converted c = convertBoth(dir, nginx, "simple.copc.laz", "simple.las");
  ASSERT_EQ(c.remote.exit_code, 0) << c.remote.err;
  ASSERT_EQ(c.local.exit_code, 0) << c.local.err;
  const PointFileHeader header = readPointFileHeader(c.remote_out);
  EXPECT_NE(header.crs.summary().find("NAD83 / Oregon"), std::string::npos) << header.crs.summary();
  // The header and the VLRs, up to the offset to the point data (bytes 96-99).
  const std::string remote = fileText(c.remote_out), local = fileText(c.local_out);
  ASSERT_GT(local.size(), 375u);
  std::uint32_t points_at = 0;
  std::memcpy(&points_at, local.data() + 96, 4);
  ASSERT_LT(points_at, local.size());
  EXPECT_EQ(remote.substr(0, points_at), local.substr(0, points_at));
  // And the records: the colours as stored (8-bit values in 16-bit fields), not scaled up.
  EXPECT_EQ(remote, local);
}

TEST(HttpConvert, APlyFromAUrlConvertsToTheLocalFilesPoints) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www");
  {
    std::ofstream ply(dir / "www" / "scan.ply", std::ios::binary);
    ply << "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
           "property double z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
           "end_header\n"
           "1.5 2.25 -3 255 0 10\n"
           "100 200.125 300 1 2 3\n"
           "-7 0 0.5 90 80 70\n";
  }
  ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
  Nginx nginx(dir / "nginx", {.root = dir / "www"});

  const Converted c = convertBoth(dir, nginx, "scan.ply", "scan.xyz");
  ASSERT_EQ(c.remote.exit_code, 0) << c.remote.err;
  ASSERT_EQ(c.local.exit_code, 0) << c.local.err;
  EXPECT_EQ(fileText(c.remote_out), fileText(c.local_out));
  const PointCloud got = readPointFile(c.remote_out);
  ASSERT_EQ(got.count, 3u);
  ASSERT_TRUE(got.hasColors());
  // Within the grid the text reader puts positions on.
  EXPECT_NEAR(got.worldY(1), 200.125, 1e-4);
  EXPECT_NEAR(got.worldX(2), -7.0, 1e-4);
  EXPECT_NEAR(got.worldZ(0), -3.0, 1e-4);
  EXPECT_EQ(got.colors[0].r, 255);
  EXPECT_EQ(got.colors[2].b, 70);
}

// A PCD file without its header is refused by the PCD reader (its name says PCD, its content
// matches no signature), from a URL as from the disk, also when a query follows the name.
TEST(HttpConvert, AQueryDoesNotHideTheFormatTheNameGives) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www");
  std::ofstream(dir / "www" / "cloud.pcd") << "1.5 2.5 3.5\n4.5 5.5 6.5\n";
  ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
  Nginx nginx(dir / "nginx", {.root = dir / "www"});
  const std::string url = nginx.url("cloud.pcd") + "?token=a.b&v=1";
  const test::RunResult remote = test::runParallax(
      dir, "convert -q " + quoted(url) + " -o " + quoted((dir / "x.xyz").string()));
  EXPECT_EQ(remote.exit_code, 2) << remote.err;
  EXPECT_NE(remote.err.find(url + ": line 1, element 'header'"), std::string::npos) << remote.err;
  EXPECT_NE(remote.err.find("expected a PCD header keyword"), std::string::npos) << remote.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.xyz"));
}

// `parallax process` takes a Potree octree's URL as it takes the local directory: the same
// bytes out (a directory URL was once opened as a file and answered 404).
TEST(HttpConvert, AProcessOfAPotreeUrlEqualsTheLocalDirectorys) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www");
  ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
  const test::RunResult built = test::runParallax(
      dir, "convert -q " + quoted(test::testDataFile("laz/ellipsoid.laz").string()) + " -o " +
               quoted((dir / "www" / "octree").string()));
  ASSERT_EQ(built.exit_code, 0) << built.err;
  Nginx nginx(dir / "nginx", {.root = dir / "www"});
  const std::string steps = " --normals 8 --outliers statistical:8,2 -q -o ";
  for (const std::string& url : {nginx.url("octree/metadata.json"), nginx.url("octree/")}) {
    SCOPED_TRACE(url);
    const test::RunResult remote = test::runParallax(
        dir, "process " + quoted(url) + steps + quoted((dir / "remote.las").string()));
    ASSERT_EQ(remote.exit_code, 0) << remote.err;
    const test::RunResult local =
        test::runParallax(dir, "process " + quoted((dir / "www" / "octree").string()) + steps +
                                   quoted((dir / "local.las").string()));
    ASSERT_EQ(local.exit_code, 0) << local.err;
    const std::string remote_bytes = fileText(dir / "remote.las");
    EXPECT_GT(readPointFileHeader(dir / "remote.las").point_count.value_or(0), 50000u);
    EXPECT_EQ(remote_bytes, fileText(dir / "local.las"));
  }
}

TEST(HttpConvert, AMissingUrlIsAnErrorNamingIt) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www");
  ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
  Nginx nginx(dir / "nginx", {.root = dir / "www"});
  const std::string url = nginx.url("nothing.laz");
  const test::RunResult r = test::runParallax(
      dir, "convert -q " + quoted(url) + " -o " + quoted((dir / "x.las").string()));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(url), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("404"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.las"));
}

}  // namespace
}  // namespace parallax
