// The on-disk range cache: ranges come back exactly, survive a new process (a new object on the
// same folder), are dropped when the server's version changes, and the folder stays within its
// budget, least recently used first.
#include "net/range_cache.h"

#include <gtest/gtest.h>

#include <numeric>
#include <thread>
#include <vector>

#include "support/temp_dir.h"

namespace parallax {
namespace {

std::vector<std::byte> pattern(std::size_t size, int seed) {
  std::vector<std::byte> bytes(size);
  for (std::size_t i = 0; i < size; ++i) bytes[i] = std::byte((i * 7 + std::size_t(seed)) & 0xff);
  return bytes;
}

const std::string kUrl = "http://127.0.0.1:1/cloud/octree.bin";
const CacheValidator kV1{.etag = "\"v1\"", .last_modified = "", .size = 1'000'000};

TEST(RangeCache, RangesComeBackWholeOrInPart) {
  test::TempDir dir;
  RangeCache cache(dir / "http", 1 << 20);
  cache.validate(kUrl, kV1);
  const auto bytes = pattern(1000, 3);
  cache.store(kUrl, 5000, bytes);
  EXPECT_TRUE(cache.contains(kUrl, {5000, 1000}));
  EXPECT_TRUE(cache.contains(kUrl, {5100, 22}));
  EXPECT_FALSE(cache.contains(kUrl, {4999, 10}));
  EXPECT_FALSE(cache.contains(kUrl, {5990, 11}));
  std::vector<std::byte> out(22);
  ASSERT_TRUE(cache.read(kUrl, 5100, out));
  EXPECT_TRUE(std::equal(out.begin(), out.end(), bytes.begin() + 100));
  EXPECT_FALSE(cache.read(kUrl, 7000, out));
  EXPECT_FALSE(cache.read("http://127.0.0.1:1/other", 5000, out));
  const RangeCacheStats stats = cache.stats();
  EXPECT_EQ(stats.hits, 1u);
  EXPECT_EQ(stats.misses, 2u);
  EXPECT_EQ(stats.total_bytes, 1000u);
}

TEST(RangeCache, KeptBetweenRunsWhileTheVersionHolds) {
  test::TempDir dir;
  const auto bytes = pattern(4096, 1);
  {
    RangeCache cache(dir / "http", 1 << 20);
    cache.validate(kUrl, kV1);
    cache.store(kUrl, 0, bytes);
  }
  RangeCache again(dir / "http", 1 << 20);
  ASSERT_TRUE(again.validator(kUrl));
  EXPECT_EQ(again.validator(kUrl)->etag, "\"v1\"");
  EXPECT_EQ(again.validator(kUrl)->size, 1'000'000u);
  EXPECT_EQ(again.stats().total_bytes, 4096u);
  again.validate(kUrl, kV1);  // the server says the same: nothing is dropped
  std::vector<std::byte> out(4096);
  ASSERT_TRUE(again.read(kUrl, 0, out));
  EXPECT_EQ(out, bytes);
}

TEST(RangeCache, ANewVersionDropsTheRanges) {
  test::TempDir dir;
  RangeCache cache(dir / "http", 1 << 20);
  cache.validate(kUrl, kV1);
  cache.store(kUrl, 0, pattern(100, 1));
  CacheValidator v2 = kV1;
  v2.etag = "\"v2\"";
  cache.validate(kUrl, v2);
  EXPECT_FALSE(cache.contains(kUrl, {0, 100}));
  EXPECT_EQ(cache.stats().total_bytes, 0u);
  EXPECT_EQ(cache.validator(kUrl)->etag, "\"v2\"");
  // A change of size alone is a new version too; so is a Last-Modified when there is no ETag.
  cache.store(kUrl, 0, pattern(100, 1));
  CacheValidator longer = v2;
  longer.size += 1;
  cache.validate(kUrl, longer);
  EXPECT_FALSE(cache.contains(kUrl, {0, 100}));
  const CacheValidator dated{.last_modified = "Mon, 01 Jan 2024 00:00:00 GMT", .size = 10};
  CacheValidator redated = dated;
  redated.last_modified = "Tue, 02 Jan 2024 00:00:00 GMT";
  cache.validate(kUrl, dated);
  cache.store(kUrl, 0, pattern(10, 2));
  cache.validate(kUrl, dated);
  EXPECT_TRUE(cache.contains(kUrl, {0, 10}));
  cache.validate(kUrl, redated);
  EXPECT_FALSE(cache.contains(kUrl, {0, 10}));
}

TEST(RangeCache, NothingIsKeptForAFileWithoutAValidator) {
  test::TempDir dir;
  RangeCache cache(dir / "http", 1 << 20);
  cache.validate(kUrl, {.size = 100});  // no ETag, no Last-Modified
  cache.store(kUrl, 0, pattern(100, 1));
  EXPECT_FALSE(cache.contains(kUrl, {0, 100}));
  EXPECT_FALSE(cache.validator(kUrl));
  // Nor for a URL never validated.
  cache.store("http://127.0.0.1:1/never", 0, pattern(100, 1));
  EXPECT_FALSE(cache.contains("http://127.0.0.1:1/never", {0, 100}));
}

TEST(RangeCache, EvictsTheLeastRecentlyUsedToStayWithinTheBudget) {
  test::TempDir dir;
  // 64 KiB budget, ranges of 8 KiB (an eighth: the largest it keeps).
  RangeCache cache(dir / "http", 64 << 10);
  cache.validate(kUrl, kV1);
  for (int i = 0; i < 8; ++i) cache.store(kUrl, std::uint64_t(i) << 13, pattern(8 << 10, i));
  EXPECT_EQ(cache.stats().total_bytes, 64u << 10);
  // Range 0 used now: it is the most recent.
  std::vector<std::byte> out(16);
  ASSERT_TRUE(cache.read(kUrl, 0, out));
  cache.store(kUrl, 8u << 13, pattern(8 << 10, 8));  // over the budget: down to 90 %
  const RangeCacheStats stats = cache.stats();
  EXPECT_LE(stats.total_bytes, (64u << 10) - (64u << 10) / 10);
  EXPECT_EQ(stats.evicted_ranges, 2u);
  EXPECT_TRUE(cache.contains(kUrl, {0, 16})) << "recently used";
  EXPECT_FALSE(cache.contains(kUrl, {1u << 13, 16})) << "the oldest";
  EXPECT_FALSE(cache.contains(kUrl, {2u << 13, 16})) << "the next oldest";
  EXPECT_TRUE(cache.contains(kUrl, {8u << 13, 16})) << "just stored";
  // The files follow: a new object counts what is on disk.
  RangeCache again(dir / "http", 64 << 10);
  EXPECT_EQ(again.stats().total_bytes, stats.total_bytes);
  // Too large for the cache: not kept.
  cache.store(kUrl, 100u << 13, pattern((8 << 10) + 1, 9));
  EXPECT_FALSE(cache.contains(kUrl, {100u << 13, 1}));
}

TEST(RangeCache, AFileRemovedBehindItsBackIsAMiss) {
  test::TempDir dir;
  RangeCache cache(dir / "http", 1 << 20);
  cache.validate(kUrl, kV1);
  cache.store(kUrl, 0, pattern(100, 1));
  // Another process evicted it.
  for (const auto& sub : std::filesystem::recursive_directory_iterator(dir / "http")) {
    if (sub.path().filename() == "0-100") std::filesystem::remove(sub.path());
  }
  std::vector<std::byte> out(100);
  EXPECT_FALSE(cache.read(kUrl, 0, out));
  EXPECT_FALSE(cache.contains(kUrl, {0, 100}));
  EXPECT_EQ(cache.stats().total_bytes, 0u);
}

TEST(RangeCache, DamagedFilesAreDroppedWhenScanned) {
  test::TempDir dir;
  {
    RangeCache cache(dir / "http", 1 << 20);
    cache.validate(kUrl, kV1);
    cache.store(kUrl, 0, pattern(100, 1));
    cache.store(kUrl, 100, pattern(100, 2));
  }
  for (const auto& sub : std::filesystem::recursive_directory_iterator(dir / "http")) {
    if (sub.path().filename() == "0-100") std::filesystem::resize_file(sub.path(), 50);
  }
  RangeCache again(dir / "http", 1 << 20);
  EXPECT_FALSE(again.contains(kUrl, {0, 100}));
  EXPECT_TRUE(again.contains(kUrl, {100, 100}));
  EXPECT_EQ(again.stats().total_bytes, 100u);
}

}  // namespace
}  // namespace parallax
