// The octree of a file over the budget, without a window: whether a file is over the budget
// (lod/large_file.h, io's header counts), where its octree goes (lod/octree_cache.h) and its
// conversion in the foreground and on a thread of its own (lod/background_octree_build.h).
// This test links parallax::lod only: `render` and `convert` need no viewer code for any of it.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "io/point_file.h"
#include "lod/background_octree_build.h"
#include "lod/large_file.h"
#include "lod/octree_cache.h"
#include "lod/potree_reader.h"
#include "lod_test_clouds.h"
#include "support/temp_dir.h"

namespace parallax::test {
namespace {

OctreeCacheSettings cacheIn(const std::filesystem::path& root) {
  OctreeCacheSettings settings;
  settings.cache_dir = root;
  settings.build.memory_bytes = 64ull << 20;
  settings.build.sampling = SamplingMethod::Random;
  return settings;
}

TEST(LargeFile, HeaderPointCountsOfPlyAndLasAndNoneForText) {
  TempDir dir;
  const PointCloud cloud = makeSurfaceCloud(321);
  writePointFile(cloud, dir / "a.ply");
  writePointFile(cloud, dir / "a.las");
  writePointFile(cloud, dir / "a.xyz");
  EXPECT_EQ(headerPointCount(dir / "a.ply"), 321u);
  EXPECT_EQ(headerPointCount(dir / "a.las"), 321u);
  EXPECT_EQ(headerPointCount(dir / "a.xyz"), std::nullopt);
  EXPECT_EQ(headerPointCount(dir / "missing.ply"), std::nullopt);
  EXPECT_EQ(headerPointCount(dir.write("broken.ply", "ply\nformat ascii 9\n")), std::nullopt);
}

TEST(LargeFile, PointsOverBudgetOnlyAboveTheBudget) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(500), dir / "a.ply");
  writePointFile(makeSurfaceCloud(500), dir / "a.las");
  for (const char* name : {"a.ply", "a.las"}) {
    SCOPED_TRACE(name);
    EXPECT_EQ(pointsOverBudget(dir / name, 499), 500u);
    EXPECT_EQ(pointsOverBudget(dir / name, 500), std::nullopt);
    EXPECT_EQ(pointsOverBudget(dir / name, 3'000'000), std::nullopt);
  }
  EXPECT_EQ(pointsOverBudget(dir / "missing.ply", 1), std::nullopt);
}

TEST(LargeFile, TextFilesOverTheBudgetAreCounted) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(2000), dir / "a.xyz");
  EXPECT_EQ(pointsOverBudget(dir / "a.xyz", 1999), 2000u);
  EXPECT_EQ(pointsOverBudget(dir / "a.xyz", 2000), std::nullopt);
  EXPECT_EQ(pointsOverBudget(dir / "a.xyz", 3'000'000), std::nullopt);
  // A comment and a header line are not points.
  dir.write("b.txt", "# scan\nx y z\n1 2 3\n4 5 6\n7 8 9\n");
  EXPECT_EQ(pointsOverBudget(dir / "b.txt", 2), 3u);
  // Not a point file: nothing to say (the ordinary read reports it).
  dir.write("c.txt", "hello world, this is not a point cloud\nat all\n");
  EXPECT_EQ(pointsOverBudget(dir / "c.txt", 1), std::nullopt);
}

TEST(OctreeCache, TextFileOverTheBudgetIsConvertedLikeTheOthers) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(5000), dir / "scan.xyz");
  const OctreeCacheSettings settings = cacheIn(dir / "cache");
  OctreeLocation location(dir / "scan.xyz", settings);
  EXPECT_TRUE(ensureOctree(location, settings.build, {}));
  EXPECT_EQ(openPotree(location.directory())->info().point_count, 5000u);
}

TEST(OctreeCache, CacheDirectoryIsNamedAfterTheFileAndReusedOnceComplete) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(2000), dir / "scan.ply");
  const OctreeCacheSettings settings = cacheIn(dir / "cache");
  OctreeLocation location(dir / "scan.ply", settings);
  EXPECT_FALSE(location.temporary());
  EXPECT_EQ(location.directory().parent_path(), dir / "cache");
  EXPECT_EQ(location.directory().filename().string().rfind("scan.ply-", 0), 0u)
      << location.directory();
  EXPECT_EQ(location.directory(), cachedOctreePath(dir / "cache", dir / "scan.ply"));
  EXPECT_FALSE(location.complete());

  EXPECT_TRUE(ensureOctree(location, settings.build, {}));
  EXPECT_TRUE(location.complete());
  EXPECT_EQ(openPotree(location.directory())->info().point_count, 2000u);
  // A second visit finds it: nothing converted.
  OctreeLocation again(dir / "scan.ply", settings);
  EXPECT_EQ(again.directory(), location.directory());
  EXPECT_TRUE(again.complete());
  EXPECT_FALSE(ensureOctree(again, settings.build, {}));
}

TEST(OctreeCache, WithoutCacheTheOctreeLivesAsLongAsItsLocation) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(800), dir / "scan.las");
  OctreeCacheSettings settings = cacheIn(dir / "unused");
  settings.use_cache = false;
  std::filesystem::path directory;
  {
    OctreeLocation location(dir / "scan.las", settings);
    EXPECT_TRUE(location.temporary());
    directory = location.directory();
    EXPECT_TRUE(ensureOctree(location, settings.build, {}));
    EXPECT_TRUE(isCompleteOctree(directory));
  }
  EXPECT_FALSE(std::filesystem::exists(directory));
  EXPECT_FALSE(std::filesystem::exists(dir / "unused"));
}

TEST(OctreeCache, ProgressNamesEveryStage) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(1500), dir / "scan.ply");
  const OctreeCacheSettings settings = cacheIn(dir / "cache");
  OctreeLocation location(dir / "scan.ply", settings);
  std::vector<std::string> stages;
  ensureOctree(location, settings.build, [&](const std::string& stage, std::uint64_t) {
    stages.push_back(stage);
    return nullptr;
  });
  ASSERT_GE(stages.size(), 3u);
  EXPECT_EQ(stages[0], "scanning");
  EXPECT_EQ(stages[1], "counting");
}

TEST(BackgroundOctreeBuild, FinishesAndHandsOverTheLocation) {
  TempDir dir;
  writePointFile(makeSurfaceCloud(3000), dir / "scan.ply");
  const OctreeCacheSettings settings = cacheIn(dir / "cache");
  auto location = std::make_unique<OctreeLocation>(dir / "scan.ply", settings);
  const std::filesystem::path directory = location->directory();
  BackgroundOctreeBuild build(std::move(location), settings.build);
  // Polled as the viewer's frame loop does, with a bound: a build that never says it finished
  // fails here rather than hanging the suite (3 000 points take well under a second).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  BackgroundOctreeBuild::Status status = build.status();
  while (!status.finished && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    status = build.status();
  }
  ASSERT_TRUE(status.finished) << "not finished after 120 s, at stage '" << status.stage << "'";
  EXPECT_EQ(status.error, "");
  EXPECT_FALSE(status.stage.empty());
  std::unique_ptr<OctreeLocation> done = build.takeLocation();
  ASSERT_NE(done, nullptr);
  EXPECT_EQ(done->directory(), directory);
  EXPECT_TRUE(done->complete());
  EXPECT_EQ(openPotree(directory)->info().point_count, 3000u);
}

TEST(BackgroundOctreeBuild, ReportsAFailedConversion) {
  TempDir dir;
  const auto broken = dir.write("broken.ply",
                                "ply\nformat ascii 1.0\nelement vertex 5\n"
                                "property float x\nproperty float y\n"
                                "property float z\nend_header\n1 2 3\n");
  const OctreeCacheSettings settings = cacheIn(dir / "cache");
  BackgroundOctreeBuild build(std::make_unique<OctreeLocation>(broken, settings), settings.build);
  std::unique_ptr<OctreeLocation> location = build.takeLocation();  // waits for the thread
  const BackgroundOctreeBuild::Status status = build.status();
  EXPECT_TRUE(status.finished);
  EXPECT_NE(status.error.find("broken.ply"), std::string::npos) << status.error;
  EXPECT_FALSE(location->complete());
}

}  // namespace
}  // namespace parallax::test
