// `parallax convert URL -o FILE --clip-box ...` of a COPC file served by nginx: the points are
// those the local file gives through its LAZ reader and the same filter, and only the nodes
// whose cube meets the box are fetched (`-v` reports them and the bytes received; nginx's
// access log says the same).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
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

// ellipsoid.copc.laz: cube x [-8242746, -8242446], y [4966506, 4966806], z [-50, 250]; a root
// and four children of 150 m. The box below lies in the low-x, low-y, low-z child alone.
constexpr const char* kBox = "-8242746,4966506,-50,-8242650,4966600,50";

TEST(HttpExtract, ARegionOfARemoteCopcFileFetchesOnlyTheNodesThatMeetIt) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "www");
  const std::filesystem::path local = dir / "www" / "ellipsoid.copc.laz";
  std::filesystem::copy_file(test::testDataFile("laz/ellipsoid.copc.laz"), local);
  ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);  // a fresh range cache
  Nginx nginx(dir / "nginx", {.root = dir / "www"});
  const std::string url = nginx.url("ellipsoid.copc.laz");

  const test::RunResult remote =
      test::runParallax(dir, "convert -v " + quoted(url) + " -o " +
                                 quoted((dir / "cut.las").string()) + " --clip-box " + kBox);
  ASSERT_EQ(remote.exit_code, 0) << remote.err;
  const test::RunResult here =
      test::runParallax(dir, "convert -q " + quoted(local.string()) + " -o " +
                                 quoted((dir / "cut-local.las").string()) + " --clip-box " + kBox);
  ASSERT_EQ(here.exit_code, 0) << here.err;

  const PointCloud got = readPointFile(dir / "cut.las");
  const PointCloud expected = readPointFile(dir / "cut-local.las");
  ASSERT_GT(expected.count, 0u);
  EXPECT_EQ(got.count, expected.count);
  EXPECT_EQ(got.bounds.min, expected.bounds.min);
  EXPECT_EQ(got.bounds.max, expected.bounds.max);

  // The report: fewer nodes than the file's five, and what came over the network.
  unsigned read = 0, all = 0;
  unsigned long long node_bytes = 0;
  const std::size_t at = remote.err.find("convert: read ");
  ASSERT_NE(at, std::string::npos) << remote.err;
  ASSERT_EQ(std::sscanf(remote.err.c_str() + at, "convert: read %u of %u nodes (%llu bytes", &read,
                        &all, &node_bytes),
            3)
      << remote.err;
  EXPECT_EQ(all, 5u);
  EXPECT_GE(read, 1u);  // the root meets every region
  EXPECT_LE(read, 2u);  // and one child at most
  // What nginx sent: the probe (the first 64 KiB: header, VLRs, the hierarchy page) and the
  // nodes read, with at most a few KiB of gaps that range merging spans; never the others'
  // chunks (here about 100 KiB).
  unsigned long long sent = 0;
  for (const test::AccessLine& line : nginx.settledAccessLog()) sent += line.bytes;
  const auto file_bytes = std::filesystem::file_size(local);
  EXPECT_GE(sent, node_bytes);
  EXPECT_LE(sent, node_bytes + (68u << 10)) << "sent " << sent << " of " << file_bytes;
  EXPECT_LT(sent, file_bytes);
}

}  // namespace
}  // namespace parallax
