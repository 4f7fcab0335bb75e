// LAS and LAZ files read from a URL by range, in-process through net's http opener, against
// nginx: a whole read, a stream of chunks and a preview give exactly the local file's points,
// the whole read in a few large requests (not one a block or a point), the preview with a small
// part of the file fetched. Bytes are counted on the server's side (its access log).
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "io/point_file.h"
#include "loopback_servers.h"
#include "net/network.h"
#include "support/run_parallax.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::Nginx;
using test::quoted;

// A scanned scene of `points` points written as LAS and LAZ (chunks of 50 000) under www/.
void writeScene(const test::TempDir& dir, std::size_t points) {
  std::filesystem::create_directories(dir / "www");
  const std::string ply = (dir / "scene.ply").string();
  ASSERT_EQ(test::runParallax(
                dir, "generate -q --points " + std::to_string(points) + " -o " + quoted(ply))
                .exit_code,
            0);
  for (const char* name : {"scene.las", "scene.laz"}) {
    const test::RunResult r = test::runParallax(
        dir, "convert -q " + quoted(ply) + " -o " + quoted((dir / "www" / name).string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
}

// The requests and body bytes nginx logged after the first `from` lines.
struct Served {
  std::size_t requests = 0;
  std::uint64_t bytes = 0;
};
Served servedSince(const Nginx& nginx, std::size_t from) {
  const std::vector<test::AccessLine> log = nginx.settledAccessLog();
  Served served;
  for (std::size_t i = from; i < log.size(); ++i) {
    ++served.requests;
    served.bytes += log[i].bytes;
  }
  return served;
}

void expectSamePoints(const PointCloud& got, const PointCloud& want, std::size_t offset = 0) {
  ASSERT_LE(got.count + offset, want.count);
  ASSERT_EQ(got.hasColors(), want.hasColors());
  for (std::size_t i = 0; i < got.count; ++i) {
    ASSERT_EQ(got.positions[i], want.positions[offset + i]) << "point " << i;
    if (got.hasColors()) {
      ASSERT_EQ(got.colors[i].r, want.colors[offset + i].r) << "point " << i;
      ASSERT_EQ(got.colors[i].b, want.colors[offset + i].b) << "point " << i;
    }
  }
}

struct RemoteScene {
  test::TempDir dir;
  std::unique_ptr<Nginx> nginx;
  RemoteScene() {
    writeScene(dir, 400'000);
    NetworkSettings settings = networkSettingsFromEnvironment();
    settings.cache_dir = dir / "cache";  // this test's, not the user's
    configureNetwork(settings);
    nginx = std::make_unique<Nginx>(dir / "nginx", Nginx::Options{.root = dir / "www"});
  }
  std::uint64_t size(const char* name) const {
    return std::filesystem::file_size(dir / "www" / name);
  }
};

TEST(HttpPointFiles, ALasFileIsReadByRangesInAFewLargeRequests) {
  RemoteScene s;
  const std::string url = s.nginx->url("scene.las");
  const PointCloud local = readPointFile(s.dir / "www" / "scene.las");
  ASSERT_EQ(local.count, 400'000u);

  const PointCloud remote = readPointFile(url);
  ASSERT_EQ(remote.count, local.count);
  expectSamePoints(remote, local);
  const Served whole = servedSince(*s.nginx, 0);
  // Detection, header and records: the file about once (blocks of 32 768 records, hinted
  // ahead and merged), not a request a block, let alone a point.
  EXPECT_GE(whole.bytes, s.size("scene.las"));
  EXPECT_LE(whole.bytes, s.size("scene.las") + (256u << 10));  // the two heads
  EXPECT_LE(whole.requests, 24u);
}

TEST(HttpPointFiles, ALasPreviewFetchesASmallPartOfTheFile) {
  RemoteScene s;
  const std::string url = s.nginx->url("scene.las");
  const PointCloud local = readPointFile(s.dir / "www" / "scene.las");
  const PointCloud preview = readPointFilePreview(url, 20'000);
  const Served served = servedSince(*s.nginx, 0);
  // Runs of consecutive records at even steps (128 records a run over a URL: 156 runs).
  ASSERT_EQ(preview.count, 156u * 128u);
  const std::size_t step = local.count / 156;
  for (std::size_t r = 0; r < 156; ++r) {
    for (std::size_t i = 0; i < 128; ++i) {
      ASSERT_EQ(preview.positions[r * 128 + i], local.positions[r * step + i])
          << "run " << r << " point " << i;
    }
  }
  EXPECT_LT(served.bytes, s.size("scene.las") / 8) << served.requests << " requests";
  EXPECT_LE(served.requests, 170u);
}

TEST(HttpPointFiles, ALasStreamGivesTheLocalFilesChunks) {
  RemoteScene s;
  const std::string url = s.nginx->url("scene.las");
  const PointCloud local = readPointFile(s.dir / "www" / "scene.las");
  std::unique_ptr<PointChunkSource> chunks = openPointChunks(url);
  ASSERT_EQ(chunks->pointCount(), local.count);
  PointCloud chunk;
  std::size_t at = 0;
  while (chunks->next(chunk, 150'000)) {
    expectSamePoints(chunk, local, at);
    at += chunk.count;
  }
  EXPECT_EQ(at, local.count);
  // A stream checks every colour before its first chunk (the 8-bit rule, las_reader.h), so the
  // records are read twice; the second time mostly from the range cache.
  const Served served = servedSince(*s.nginx, 0);
  EXPECT_LE(served.bytes, 2 * s.size("scene.las") + (256u << 10));
  EXPECT_LE(served.requests, 60u);
}

TEST(HttpPointFiles, ALazFileIsReadByChunksAndItsPreviewFetchesFewOfThem) {
  RemoteScene s;
  const std::string url = s.nginx->url("scene.laz");
  const PointCloud local = readPointFile(s.dir / "www" / "scene.laz");
  const PointCloud local_preview = readPointFilePreview(s.dir / "www" / "scene.laz", 20'000);

  const PointCloud preview = readPointFilePreview(url, 20'000);
  const Served first = servedSince(*s.nginx, 0);
  ASSERT_EQ(preview.count, local_preview.count);
  ASSERT_GT(preview.count, 10'000u);
  expectSamePoints(preview, local_preview);
  // The header, the chunk table from the end, and the chunks the sample needs.
  EXPECT_LT(first.bytes, s.size("scene.laz") / 4) << first.requests << " requests";

  const PointCloud remote = readPointFile(url);
  ASSERT_EQ(remote.count, local.count);
  expectSamePoints(remote, local);
  const Served whole = servedSince(*s.nginx, first.requests);
  EXPECT_LE(whole.bytes, s.size("scene.laz") + (256u << 10));
  EXPECT_LE(whole.requests, 24u);  // 8 chunks of 50 000 points
}

}  // namespace
}  // namespace parallax
