// The whole of `process` within --memory on a text input (xyz): the reading passes, the tiles,
// the steps and the text output each hold a batch, never the cloud. The binary formats' streaming
// is bounded by io's tests (LasStreamWriter and TextStreamWriter .HoldsABatchNotTheFile); this is
// the text path end to end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <string>

#include "io/point_file.h"
#include "process/process_runner.h"
#include "process/tile_queries.h"
#include "process/tile_set.h"
#include "support/allocation_counter.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

// printf into a std::string.
template <typename... Args>
std::string format(const char* pattern, Args... args) {
  char line[128];
  const int n = std::snprintf(line, sizeof line, pattern, args...);
  return std::string(line, std::size_t(std::max(n, 0)));
}

// An xyz text file's lines, line(i) for i in [0, count).
template <typename Line>
std::string textLines(std::size_t count, Line line) {
  std::string text;
  for (std::size_t i = 0; i < count; ++i) text += line(i);
  return text;
}

TEST(ProcessMemory, ATextInputIsStreamedNotHeld) {
  // 60 000 points of a hilly strip, at --memory 1: slabs of 4 096 points, read in batches of
  // 4 096. Held whole, the cloud's positions alone would be one 720 KB column (1.4 MB as
  // doubles) and its text 1.6 MB; a batch's columns are 50 KB, a slab's records 128 KB and the
  // x histogram that cuts the slabs 512 KB. No single allocation may reach 640 KB (malloc, new
  // and anonymous mmap counted: allocation_counter.h). Read in the 1 M-point batches of a
  // large --memory, the whole cloud is one batch, and this fails.
  constexpr std::size_t kPoints = 60000;
  test::TempDir dir;
  std::mt19937 random(26);
  std::uniform_real_distribution<double> along(0.0, 250.0), across(0.0, 40.0);
  const auto in = dir.write("strip.xyz", textLines(kPoints, [&](std::size_t i) {
                              const double x = along(random), y = across(random);
                              const double z = 3.0 * std::sin(x / 17.0) + 2.0 * std::cos(y / 11.0);
                              return format("%.3f %.3f %.3f %zu\n", x, y, z, i % 251);
                            }));
  ProcessOptions options;
  options.inputs = {ConvertInput{.path = in, .text_columns = {"x", "y", "z", "intensity"}}};
  options.output = dir / "out.xyz";
  SubsampleStep voxel;
  voxel.method = SubsampleStep::Method::kVoxel;
  voxel.size = 0.25;
  options.steps = {NormalsStep{.k = 8}, voxel};
  options.memory_mb = 1;
  ProcessReport report;
  std::uint64_t largest = 0;
  {
    test::AllocationScope allocations;
    report = runProcess(options);
    largest = allocations.largest();
  }
  EXPECT_LT(largest, std::uint64_t(640) << 10);
  EXPECT_EQ(report.input_points, kPoints);
  EXPECT_GE(report.tiles, 14u);  // really tiled: 60 000 / 4 096
  // Voxels of 0.25 m over 250 x 40 m (160 000 of them): most hold one point, some two.
  EXPECT_GT(report.output_points, kPoints * 7 / 10);
  EXPECT_LT(report.output_points, kPoints);
  const PointCloud out = readPointFile(options.output);
  ASSERT_EQ(out.count, report.output_points);
  ASSERT_TRUE(out.hasNormals());
  // The strip's normals point up (--orient up) and are unit vectors.
  for (std::size_t i = 0; i < out.count; i += 997) {
    const Float3 n = out.normals[i];
    EXPECT_NEAR(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z, 1.0, 1e-4) << i;
    EXPECT_GT(n.z, 0.5f) << i;
  }
}

TEST(ProcessMemory, LoadBoxAllocatesWhatItLoadsOnce) {
  // 30 000 points spilled into slabs of 4 096 (batches of 4 096), all loaded by one box: the
  // result is reserved once for the overlapping slabs' points (30 000 x 24 bytes) besides the
  // read buffers (4 096 x 25 bytes a slab). Grown by push_back instead, the vector is allocated again
  // at each doubling (1, 2, 4 ... 32 768 points: about 2 x 32 768 x 24 bytes), and this fails.
  constexpr std::size_t kPoints = 30000;
  test::TempDir dir;
  const auto in =
      dir.write("strip.xyz", textLines(kPoints, [](std::size_t i) {
                  return format("%.3f %.3f %.3f\n", double(i % 3000) * 0.1, double(i / 3000), 0.5);
                }));
  const TileSet set = TileSet::spill({ConvertInput{.path = in, .text_columns = {"x", "y", "z"}}},
                                     dir.path(), "t", 4096, nullptr, {});
  ASSERT_GE(set.tiles(), 7u);
  const double lo[3] = {-1.0, -1.0, -1.0}, hi[3] = {1000.0, 1000.0, 1000.0};
  std::vector<GridPoint> out;
  std::uint64_t bytes = 0;
  {
    test::AllocationScope allocations;
    set.appendKeptInBox(lo, hi, SIZE_MAX, out);
    bytes = allocations.bytes();
  }
  ASSERT_EQ(out.size(), kPoints);
  // Each slab read allocates its block and flags buffers once.
  const std::uint64_t buffers = set.tiles() * set.batchPoints() * (sizeof(GridPoint) + 1);
  EXPECT_LE(bytes, kPoints * sizeof(GridPoint) + buffers + (64u << 10));
}

TEST(ProcessMemory, LaterRoundsLoadTheirQueriesSurroundingsNotTheSlab) {
  // A gently rolling ground (100 x 100 m, 9 838 points) and 100 bogus returns 60-100 m above it
  // (aerial LAS files have such), at --memory 1: three slabs of at most 4 096 points. A bogus
  // return's 16th neighbour, another bogus return about 30 m away, lies outside its slab, so its
  // query is asked again in a later round, as are the sparse strip's near the slabs' edges. One
  // box around all pending queries, grown by the farthest reach (the code before), takes the
  // slab and its neighbours from the ground up: 9 938 points, the whole cloud, and this fails.
  // A ball per query takes what lies within its own reach: 146 points in the largest round
  // (bounded here by a tenth of a slab). Either way the bytes are the one-slab run's.
  test::TempDir dir;
  std::mt19937 random(2611);
  std::uniform_real_distribution<double> across(0.0, 100.0), up(60.0, 100.0);
  std::string text;
  auto ground = [&](double x, double y) {
    text += format("%.3f %.3f %.3f\n", x, y, 0.3 * std::sin(x / 7.0) + 0.2 * std::cos(y / 5.0));
  };
  for (std::size_t i = 0; i < 9600; ++i) ground(double(i % 120) * (100.0 / 120.0), double(i / 120));
  // A sparse strip (a point every 3 m): there a query's 16th neighbour lies beyond the first
  // halo (sized for the dense ground), so near the slabs' edges its queries are pending too.
  for (double y = 81.0; y < 100.0; y += 3.0) {
    for (double x = 0.5; x < 100.0; x += 3.0) ground(x, y);
  }
  for (std::size_t i = 0; i < 100; ++i) {
    const double x = across(random), y = across(random), z = up(random);
    text += format("%.3f %.3f %.3f\n", x, y, z);
  }
  const auto in = dir.write("aerial.xyz", text);
  auto run = [&](const std::string& name, std::uint64_t memory_mb) {
    ProcessOptions options;
    options.inputs = {ConvertInput{.path = in, .text_columns = {"x", "y", "z"}}};
    options.output = dir / name;
    options.steps = {NormalsStep{.k = 16}};
    options.memory_mb = memory_mb;
    return runProcess(options);
  };
  const ProcessReport tiled = run("tiled.ply", 1);
  const ProcessReport whole = run("whole.ply", 16000);
  EXPECT_EQ(tiled.tiles, 3u);
  EXPECT_EQ(whole.tiles, 1u);
  // The later rounds happened (the bogus returns' queries), and each loaded little.
  EXPECT_GE(tiled.later_rounds.later_rounds, 3u);
  EXPECT_LE(tiled.later_rounds.largest_later_round, 400u);
  EXPECT_LE(tiled.later_rounds.later_round_points, 2000u);
  EXPECT_EQ(whole.later_rounds.later_rounds, 0u);
  auto bytes = [](const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  const std::string a = bytes(dir / "tiled.ply");
  EXPECT_GT(a.size(), 9938u * 12u);  // at least the normals
  EXPECT_TRUE(a == bytes(dir / "whole.ply"));
}

TEST(ProcessMemory, BallBatchesHoldEveryBallWithinTheLimit) {
  // A 60 x 60 m grid (a point a metre, 3 600) in slabs of 1 024 points, every 9th point removed
  // (not kept), and 150 balls of radius 4-7 m around points of it: together they hold about
  // 2 900 points. Loaded in batches of at most 500: each batch is a run of the balls in their
  // order (the next starting where the last ended), holds no point twice, and holds exactly the
  // kept points within its balls (counted here against every point of the cloud). Loaded at once,
  // as before the batches, the one batch holds them all, and this fails.
  test::TempDir dir;
  const auto in = dir.write("grid.xyz", textLines(3600, [](std::size_t i) {
                              return format("%zu %zu %.1f\n", i % 60, i / 60, double(i % 7) * 0.1);
                            }));
  const TileSet set = TileSet::spill({ConvertInput{.path = in, .text_columns = {"x", "y", "z"}}},
                                     dir.path(), "b", 1024, nullptr, {});
  ASSERT_GE(set.tiles(), 4u);
  std::vector<GridPoint> cloud;
  for (std::size_t t = 0; t < set.tiles(); ++t) {
    std::vector<GridPoint> points = set.readPoints(t);
    std::vector<std::uint8_t> kept(points.size(), 1);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (points[i].id % 9 == 4) kept[i] = 0;
      if (kept[i]) cloud.push_back(points[i]);
    }
    set.writeRecords<std::uint8_t>(t, "kept", kept);
  }
  std::vector<GridPoint> queries;
  std::vector<std::uint32_t> pending;
  std::vector<double> halos;
  std::mt19937 random(4);
  std::uniform_int_distribution<std::size_t> pick(0, cloud.size() - 1);
  std::uniform_real_distribution<double> radius(4.0, 7.0);
  for (std::uint32_t j = 0; j < 150; ++j) {
    queries.push_back(cloud[pick(random)]);
    pending.push_back(j);
    halos.push_back(radius(random));
  }
  std::vector<BallGroup> groups;
  std::vector<QueryBall> balls;
  std::vector<std::uint32_t> ball_of;
  groupQueryBalls(queries, pending, halos, groups, balls, ball_of);
  auto inBall = [](const GridPoint& p, const QueryBall& b) {
    return squaredDistance(p.x, p.y, p.z, b.x, b.y, b.z) <= b.r2;
  };
  std::size_t everything = 0;  // the kept points within some ball
  for (const GridPoint& p : cloud) {
    everything += std::any_of(balls.begin(), balls.end(), [&](auto& b) { return inBall(p, b); });
  }
  ASSERT_GT(everything, 2000u);
  constexpr std::uint64_t kLimit = 500;
  BallBatches batches(set, groups, balls, kLimit);
  std::vector<GridPoint> points;
  std::uint32_t expected_from = 0;
  std::size_t loaded = 0;
  while (batches.next(points)) {
    ASSERT_EQ(batches.from(), expected_from);
    ASSERT_GT(batches.to(), batches.from());
    expected_from = batches.to();
    EXPECT_LE(points.size(), kLimit) << "balls " << batches.from() << "-" << batches.to();
    std::set<std::uint64_t> ids;
    for (const GridPoint& p : points) ids.insert(p.id);
    EXPECT_EQ(ids.size(), points.size()) << "a point loaded twice";
    const auto first = balls.begin() + batches.from(), last = balls.begin() + batches.to();
    std::size_t within = 0;
    for (const GridPoint& p : cloud) {
      within += std::any_of(first, last, [&](auto& b) { return inBall(p, b); });
    }
    EXPECT_EQ(points.size(), within) << "balls " << batches.from() << "-" << batches.to();
    for (const GridPoint& p : points) {
      EXPECT_TRUE(p.id % 9 != 4 && std::any_of(first, last, [&](auto& b) { return inBall(p, b); }));
    }
    loaded += points.size();
  }
  EXPECT_EQ(expected_from, balls.size());
  // Batches of at most 500 from 2 000 or more points: at least five, each (but the last) full
  // enough that a sixth of the limit would not fit beside it.
  EXPECT_GE(batches.batches(), everything / kLimit + 1);
  EXPECT_LE(batches.batches(), 3 * everything / kLimit);
  EXPECT_EQ(batches.passes(), batches.batches() + 1);  // one more: the round counted first
  EXPECT_EQ(batches.points(), loaded);
  EXPECT_LE(batches.largest(), kLimit);
}

TEST(ProcessMemory, ALaterRoundHoldsAtMostASlab) {
  // A dense 60 x 30 m ground (a point every 0.5 m, 7 200) beside a sparse one 120 m long (a
  // point every 4 m, 450), K = 200 normals at --memory 1: two slabs of at most 4 096 points.
  // A slab's first halo is sized for its dense part, so the sparse part's queries, whose 200th
  // neighbour lies tens of metres away, are asked again. Before, a later round loaded balls of
  // its queries' halos doubled (or the reach their answers needed, whichever was larger), all at
  // once: 4 400 and 4 931 points, more than a slab, and this fails. Balls of the reach alone,
  // loaded in batches of at most a slab (BallBatches), keep each within --memory's share; the
  // bytes are the one-slab run's.
  test::TempDir dir;
  std::string text;
  auto ground = [&](double x, double y) {
    text += format("%.3f %.3f %.3f\n", x, y, 0.3 * std::sin(x / 7.0) + 0.2 * std::cos(y / 5.0));
  };
  for (std::size_t i = 0; i < 120 * 60; ++i) ground(double(i % 120) * 0.5, double(i / 120) * 0.5);
  for (std::size_t i = 0; i < 15 * 30; ++i) {
    ground(2.0 + double(i % 15) * 4.0, 32.0 + double(i / 15) * 4.0);
  }
  const auto in = dir.write("two_densities.xyz", text);
  auto run = [&](const std::string& name, std::uint64_t memory_mb) {
    ProcessOptions options;
    options.inputs = {ConvertInput{.path = in, .text_columns = {"x", "y", "z"}}};
    options.output = dir / name;
    options.steps = {NormalsStep{.k = 200}};
    options.memory_mb = memory_mb;
    return runProcess(options);
  };
  const ProcessReport tiled = run("tiled.ply", 1);
  const ProcessReport whole = run("whole.ply", 16000);
  EXPECT_EQ(tiled.tiles, 2u);
  EXPECT_EQ(whole.tiles, 1u);
  EXPECT_GE(tiled.later_rounds.later_rounds, 1u);
  // --memory 1: slabs of 1 MB / kProcessBytesPerPoint = 4 096 points, a later round's share.
  EXPECT_LE(tiled.later_rounds.largest_later_round, 4096u);
  auto bytes = [](const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  const std::string a = bytes(dir / "tiled.ply");
  EXPECT_GT(a.size(), 7650u * 12u);  // at least the normals
  EXPECT_TRUE(a == bytes(dir / "whole.ply"));
}

}  // namespace
}  // namespace parallax
