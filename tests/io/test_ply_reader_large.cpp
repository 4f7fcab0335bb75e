// Large files and streaming: parallel decoding cuts the body into ranges and PlyChunkReader hands
// it out in chunks; every point must land in its place, in file order, with its exact value.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/ply_reader.h"
#include "io/ply_test_files.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::asBytes;
using test::colors;
using test::expectSamePoints;
using test::kAllPlyFormats;
using test::PlyBody;
using test::plyHeader;
using test::positionFile;
using test::readPlyText;
using test::World;
using test::worldPositions;

// ---------------------------------------------------------------------------------------------
// Large files: parallel decoding splits the body into chunks; every point must land in its
// place with its exact value.

constexpr std::size_t kLargeCount = 300'000;

World largePoint(std::size_t i) {
  return {596000.0 + double(i) * 0.25, 4200000.125 + double(i % 1000) * 0.5,
          -double(i % 37) * 0.125};
}

// kLargeCount points; `faces_before` face records (lists of 3 or 4) precede the vertices and
// `faces_after` follow them.
std::string largeFile(PlyFormat format, bool with_lists, std::string_view eol = "\n",
                      std::size_t faces_before = 0, std::size_t faces_after = 0) {
  std::string header = plyHeader(format, {});
  std::string lines;
  if (faces_before > 0) {
    lines += "element face " + std::to_string(faces_before) +
             "\nproperty list uchar uint vertex_indices\n";
  }
  lines += "element vertex " + std::to_string(kLargeCount) +
           "\nproperty double x\nproperty double y\nproperty double z\n"
           "property uchar red\nproperty uchar green\nproperty uchar blue\n"
           "property float quality\n";
  if (with_lists) lines += "property list uchar int ids\n";
  if (faces_after > 0) {
    lines += "element face " + std::to_string(faces_after) +
             "\nproperty list uchar uint vertex_indices\n";
  }
  header.insert(header.find("end_header"), lines);
  PlyBody body(format);
  auto put_faces = [&](std::size_t count) {
    for (std::size_t f = 0; f < count; ++f) {
      std::uint8_t corners = 3 + f % 2;
      body.put(corners);
      for (std::uint32_t k = 0; k < corners; ++k) body.put(std::uint32_t(f + k));
      body.end(eol);
    }
  };
  put_faces(faces_before);
  for (std::size_t i = 0; i < kLargeCount; ++i) {
    World p = largePoint(i);
    body.put(p[0]).put(p[1]).put(p[2]).put(std::uint8_t(i)).put(std::uint8_t(i >> 8));
    body.put(std::uint8_t(i >> 16)).put(float(i) * 0.5f);
    if (with_lists) {
      body.put(std::uint8_t(i % 5));
      for (std::size_t k = 0; k < i % 5; ++k) body.put(std::int32_t(i + k));
    }
    body.end(eol);
  }
  put_faces(faces_after);
  return header + body.bytes();
}

void expectLargeValues(const PointCloud& cloud) {
  ASSERT_EQ(cloud.count, kLargeCount);
  ASSERT_EQ(cloud.colors.size(), kLargeCount);
  const ScalarColumn* quality = cloud.findScalar("quality");
  ASSERT_NE(quality, nullptr);
  ASSERT_EQ(quality->type, ScalarType::Float32);
  for (std::size_t i = 0; i < kLargeCount; ++i) {
    World p = largePoint(i);
    ASSERT_EQ(cloud.worldX(i), p[0]) << "point " << i;
    ASSERT_EQ(cloud.worldY(i), p[1]) << "point " << i;
    ASSERT_EQ(cloud.worldZ(i), p[2]) << "point " << i;
    ASSERT_EQ(cloud.colors[i],
              (Rgba8{std::uint8_t(i), std::uint8_t(i >> 8), std::uint8_t(i >> 16), 255}))
        << "point " << i;
    ASSERT_EQ(quality->as<float>()[i], float(i) * 0.5f) << "point " << i;
  }
}

TEST(PlyReaderLarge, BinaryParallelEqualsSerialInFileOrder) {
  for (PlyFormat format : {PlyFormat::BinaryLittleEndian, PlyFormat::BinaryBigEndian}) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string file = largeFile(format, /*with_lists=*/false);
    PointCloud parallel = readPlyText(file, true);
    PointCloud serial = readPlyText(file, false);
    expectLargeValues(parallel);
    expectLargeValues(serial);
    expectSamePoints(parallel, serial);
  }
}

TEST(PlyReaderLarge, AsciiParallelEqualsSerialInFileOrder) {
  std::string file = largeFile(PlyFormat::Ascii, /*with_lists=*/false);
  PointCloud parallel = readPlyText(file, true);
  PointCloud serial = readPlyText(file, false);
  expectLargeValues(parallel);
  expectLargeValues(serial);
  expectSamePoints(parallel, serial);
}

TEST(PlyReaderLarge, VariableLengthListsParallelEqualsSerial) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string file = largeFile(format, /*with_lists=*/true);
    PointCloud parallel = readPlyText(file, true);
    PointCloud serial = readPlyText(file, false);
    expectLargeValues(parallel);
    expectSamePoints(parallel, serial);
  }
}

TEST(PlyReaderLarge, AsciiCrlfParallelEqualsSerial) {
  std::string file = largeFile(PlyFormat::Ascii, /*with_lists=*/false, "\r\n");
  PointCloud parallel = readPlyText(file, true);
  PointCloud serial = readPlyText(file, false);
  expectLargeValues(parallel);
  expectSamePoints(parallel, serial);
}

TEST(PlyReaderLarge, ManyFacesBeforeTheVertices) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string file = largeFile(format, /*with_lists=*/false, "\n", /*faces_before=*/100'001);
    PointCloud parallel = readPlyText(file, true);
    PointCloud serial = readPlyText(file, false);
    expectLargeValues(parallel);
    expectSamePoints(parallel, serial);
  }
}

TEST(PlyReaderLarge, ManyFacesAfterTheVertices) {
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string file =
        largeFile(format, /*with_lists=*/true, "\n", /*faces_before=*/0, /*faces_after=*/200'003);
    PointCloud parallel = readPlyText(file, true);
    expectLargeValues(parallel);
    expectSamePoints(parallel, readPlyText(file, false));
  }
}

// One far outlier among 300k points, at an index a strided sample skips: readPly must still
// hold every point exactly (it has no streaming limitation), and report progress once.
TEST(PlyReaderLarge, OutlierTheSampleMissesIsStillExact) {
  struct Counter : Progress {
    std::atomic<std::uint64_t> total{0};
    void advance(std::uint64_t amount) override { total += amount; }
  };
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    auto expected = [](std::size_t i) -> World {
      if (i == 1) return {1.0e6, -2.0e6, 3.0e6};
      return {double(i % 1024) / 1024.0, double(i % 512) / 512.0, double(i % 7)};
    };
    std::string header = plyHeader(format, {});
    header.insert(header.find("end_header"),
                  "element vertex " + std::to_string(kLargeCount) +
                      "\nproperty double x\nproperty double y\nproperty double z\n");
    PlyBody body(format);
    for (std::size_t i = 0; i < kLargeCount; ++i) {
      World p = expected(i);
      body.put(p[0]).put(p[1]).put(p[2]).end();
    }
    std::string file = header + body.bytes();
    for (bool parallel : {true, false}) {
      Counter counter;
      PlyReadOptions options;
      options.parallel = parallel;
      options.progress = &counter;
      PointCloud cloud = readPlyFromMemory(asBytes(file), "outlier.ply", options);
      ASSERT_EQ(cloud.count, kLargeCount);
      for (std::size_t i = 0; i < kLargeCount; ++i) {
        World p = expected(i);
        ASSERT_EQ(cloud.worldX(i), p[0]) << i;
        ASSERT_EQ(cloud.worldY(i), p[1]) << i;
        ASSERT_EQ(cloud.worldZ(i), p[2]) << i;
      }
      EXPECT_EQ(cloud.bounds.min, (World{0.0, -2.0e6, 0.0}));
      EXPECT_EQ(cloud.bounds.max, (World{1.0e6, 511.0 / 512.0, 3.0e6}));
      EXPECT_EQ(counter.total.load(), kLargeCount);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// PlyChunkReader

PointCloud readAllChunks(PlyChunkReader& reader, std::size_t max_points,
                         std::vector<std::size_t>* sizes = nullptr) {
  PointCloud all;
  std::vector<World> world;
  std::vector<Rgba8> rgba;
  PointCloud chunk;
  std::size_t guard = 0;
  while (reader.next(chunk, max_points)) {
    EXPECT_GT(chunk.count, 0u);
    EXPECT_LE(chunk.count, max_points);
    EXPECT_EQ(chunk.positions.size(), chunk.count);
    EXPECT_EQ(chunk.quantization, reader.quantization());
    if (sizes) sizes->push_back(chunk.count);
    for (std::size_t i = 0; i < chunk.count; ++i) {
      world.push_back({chunk.worldX(i), chunk.worldY(i), chunk.worldZ(i)});
    }
    rgba.insert(rgba.end(), chunk.colors.begin(), chunk.colors.end());
    if (++guard > reader.pointCount() + 2) {
      ADD_FAILURE() << "next() never returns false";
      break;
    }
  }
  EXPECT_EQ(chunk.count, 0u) << "the chunk is empty at the end";
  // Rebuild one cloud in identity quantization from the exact world values (all tests use
  // integral world values for this).
  all.count = world.size();
  all.positions = Column<Int3>(world.size());
  for (std::size_t i = 0; i < world.size(); ++i) {
    all.positions[i] = {std::int32_t(world[i][0]), std::int32_t(world[i][1]),
                        std::int32_t(world[i][2])};
    EXPECT_EQ(double(all.positions[i].x), world[i][0]);
  }
  all.colors = Column<Rgba8>(rgba.size());
  for (std::size_t i = 0; i < rgba.size(); ++i) all.colors[i] = rgba[i];
  return all;
}

// Integer positions (x rising, y periodic, z rising), colours, an optional list in the vertex
// element, then a face element.
std::string chunkTestFile(PlyFormat format, std::size_t count, bool with_lists) {
  std::string header = plyHeader(format, {});
  std::string lines = "element vertex " + std::to_string(count) +
                      "\nproperty int x\nproperty int y\nproperty int z\n";
  if (with_lists) lines += "property list uchar int ids\n";
  lines +=
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element face 1\nproperty list uchar int vertex_indices\n";
  header.insert(header.find("end_header"), lines);
  PlyBody body(format);
  for (std::size_t i = 0; i < count; ++i) {
    body.put(std::int32_t(i) - 5000).put(std::int32_t(i % 100)).put(std::int32_t(i * 3));
    if (with_lists) {
      body.put(std::uint8_t(i % 3));
      for (std::size_t k = 0; k < i % 3; ++k) body.put(std::int32_t(k));
    }
    body.put(std::uint8_t(i)).put(std::uint8_t(i * 7)).put(std::uint8_t(250)).end();
  }
  body.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2).end();
  return header + body.bytes();
}

void expectChunksEqualReadPly(bool with_lists) {
  test::TempDir dir;
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    auto path = dir.write("chunks_" + test::formatKeyword(format) + ".ply",
                          chunkTestFile(format, 10'007, with_lists));
    try {
      PointCloud whole = readPly(path);
      ASSERT_EQ(whole.count, 10'007u);
      PlyChunkReader reader(path);
      EXPECT_EQ(reader.pointCount(), 10'007u);
      PointCloud joined = readAllChunks(reader, 1000);
      ASSERT_EQ(joined.count, whole.count);
      for (std::size_t i = 0; i < whole.count; ++i) {
        ASSERT_EQ(joined.worldX(i), whole.worldX(i)) << i;
        ASSERT_EQ(joined.worldY(i), whole.worldY(i)) << i;
        ASSERT_EQ(joined.worldZ(i), whole.worldZ(i)) << i;
        ASSERT_EQ(joined.worldX(i), double(std::int32_t(i) - 5000)) << i;
      }
      EXPECT_EQ(colors(joined), colors(whole));
    } catch (const std::exception& error) {
      ADD_FAILURE() << "threw: " << error.what();
    }
  }
}

TEST(PlyChunkReader, ChunksConcatenatedEqualReadPly) {
  expectChunksEqualReadPly(/*with_lists=*/false);
}

TEST(PlyChunkReader, ChunksConcatenatedEqualReadPlyWithListsInTheVertexElement) {
  expectChunksEqualReadPly(/*with_lists=*/true);
}

TEST(PlyChunkReader, ChunkSizesAreHonoured) {
  test::TempDir dir;
  for (bool with_lists : {false, true}) {
    auto path =
        dir.write("sizes.ply", chunkTestFile(PlyFormat::BinaryLittleEndian, 2500, with_lists));
    for (std::size_t max_points : {1, 7, 1000, 2500, 100000}) {
      SCOPED_TRACE(std::to_string(max_points) + (with_lists ? " with lists" : ""));
      try {
        PlyChunkReader reader(path);
        std::vector<std::size_t> sizes;
        PointCloud joined = readAllChunks(reader, max_points, &sizes);
        EXPECT_EQ(joined.count, 2500u);
        std::size_t total = 0;
        for (std::size_t size : sizes) total += size;
        EXPECT_EQ(total, 2500u);
        EXPECT_GE(sizes.size(), (2500 + max_points - 1) / max_points);
      } catch (const std::exception& error) {
        ADD_FAILURE() << "threw: " << error.what();
      }
    }
  }
}

TEST(PlyChunkReader, HeaderIsAvailableBeforeTheFirstChunk) {
  test::TempDir dir;
  auto path = dir.write("header.ply", chunkTestFile(PlyFormat::BinaryBigEndian, 10, true));
  PlyChunkReader reader(path);
  EXPECT_EQ(reader.header().format, PlyFormat::BinaryBigEndian);
  ASSERT_EQ(reader.header().elements.size(), 2u);
  EXPECT_EQ(reader.header().elements[0].name, "vertex");
  EXPECT_EQ(reader.header().elements[1].name, "face");
  EXPECT_EQ(reader.pointCount(), 10u);
}

TEST(PlyChunkReader, GivenQuantizationIsUsed) {
  test::TempDir dir;
  std::vector<World> points = {{100.5, 200.25, 300.0}, {101.0, 199.75, 299.5}, {99.0, 200, 301}};
  auto path =
      dir.write("quantized.ply", positionFile(PlyFormat::BinaryLittleEndian, "double", points));
  PlyChunkReader reader(path);
  Quantization given;
  given.scale = {0.5, 0.25, 0.5};
  given.offset = {100.0, 200.0, 300.0};
  reader.setQuantization(given);
  EXPECT_EQ(reader.quantization(), given);
  PointCloud chunk;
  ASSERT_TRUE(reader.next(chunk, 10));
  EXPECT_EQ(chunk.quantization, given);
  ASSERT_EQ(chunk.count, 3u);
  EXPECT_EQ(chunk.positions[0], (Int3{1, 1, 0}));
  EXPECT_EQ(chunk.positions[1], (Int3{2, -1, -1}));
  EXPECT_EQ(chunk.positions[2], (Int3{-2, 0, 2}));
  EXPECT_EQ(worldPositions(chunk), points);
  EXPECT_FALSE(reader.next(chunk, 10));
  EXPECT_EQ(chunk.count, 0u);
}

TEST(PlyChunkReader, ChosenQuantizationHoldsEveryPointExactly) {
  test::TempDir dir;
  std::string file = largeFile(PlyFormat::BinaryLittleEndian, /*with_lists=*/false);
  auto path = dir.write("large.ply", file);
  PlyChunkReader reader(path);
  PointCloud chunk;
  std::size_t index = 0;
  while (reader.next(chunk, 65536)) {
    for (std::size_t i = 0; i < chunk.count; ++i, ++index) {
      World p = largePoint(index);
      ASSERT_EQ(chunk.worldX(i), p[0]) << index;
      ASSERT_EQ(chunk.worldY(i), p[1]) << index;
      ASSERT_EQ(chunk.worldZ(i), p[2]) << index;
    }
  }
  EXPECT_EQ(index, kLargeCount);
}

// Chunks that straddle the reader's internal ranges, in every format, with lists in the vertex
// element, faces on both sides and CRLF line ends in ascii.
TEST(PlyChunkReader, LargeFilesInOddChunksEqualReadPly) {
  test::TempDir dir;
  for (PlyFormat format : kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    auto path = dir.write("large.ply", largeFile(format, /*with_lists=*/true, "\r\n",
                                                 /*faces_before=*/1001, /*faces_after=*/999));
    try {
      PointCloud whole = readPly(path);
      expectLargeValues(whole);
      PlyChunkReader reader(path);
      PointCloud chunk;
      std::size_t index = 0;
      while (reader.next(chunk, 7777)) {
        ASSERT_LE(chunk.count, 7777u);
        for (std::size_t i = 0; i < chunk.count; ++i, ++index) {
          ASSERT_EQ(chunk.worldX(i), whole.worldX(index)) << index;
          ASSERT_EQ(chunk.worldY(i), whole.worldY(index)) << index;
          ASSERT_EQ(chunk.worldZ(i), whole.worldZ(index)) << index;
          ASSERT_EQ(chunk.colors[i], whole.colors[index]) << index;
        }
      }
      EXPECT_EQ(index, kLargeCount);
    } catch (const std::exception& error) {
      ADD_FAILURE() << "threw: " << error.what();
    }
  }
}

// A file of a few hundred bytes: the sampled quantization must still cover every point.
TEST(PlyChunkReader, SmallFilesStreamInEveryFormat) {
  test::TempDir dir;
  for (PlyFormat format : kAllPlyFormats) {
    for (bool with_lists : {false, true}) {
      SCOPED_TRACE(test::formatKeyword(format) + (with_lists ? " with lists" : ""));
      auto path = dir.write("small.ply", chunkTestFile(format, 25, with_lists));
      try {
        PlyChunkReader reader(path);
        std::vector<std::size_t> sizes;
        PointCloud joined = readAllChunks(reader, 10, &sizes);
        ASSERT_EQ(joined.count, 25u);
        for (std::size_t i = 0; i < 25; ++i) {
          ASSERT_EQ(joined.worldX(i), double(std::int32_t(i) - 5000)) << i;
          ASSERT_EQ(joined.worldY(i), double(i % 100)) << i;
          ASSERT_EQ(joined.worldZ(i), double(i * 3)) << i;
        }
      } catch (const std::exception& error) {
        ADD_FAILURE() << "threw: " << error.what();
      }
    }
  }
}

TEST(PlyChunkReader, MovedReaderContinuesWhereItWas) {
  test::TempDir dir;
  auto path =
      dir.write("move.ply", chunkTestFile(PlyFormat::BinaryLittleEndian, 25, /*with_lists=*/false));
  PlyChunkReader first(path);
  PointCloud chunk;
  ASSERT_TRUE(first.next(chunk, 10));
  EXPECT_EQ(chunk.worldX(0), -5000.0);
  PlyChunkReader second(std::move(first));
  std::size_t seen = chunk.count;
  while (second.next(chunk, 10)) {
    EXPECT_EQ(chunk.worldX(0), double(std::int32_t(seen) - 5000));
    seen += chunk.count;
  }
  EXPECT_EQ(seen, 25u);
}

TEST(PlyChunkReader, EmptyVertexElementHasNoChunk) {
  test::TempDir dir;
  auto path = dir.write("empty.ply", plyHeader(PlyFormat::BinaryLittleEndian,
                                               {"element vertex 0", "property float x",
                                                "property float y", "property float z"}));
  PlyChunkReader reader(path);
  EXPECT_EQ(reader.pointCount(), 0u);
  PointCloud chunk;
  EXPECT_FALSE(reader.next(chunk, 100));
  EXPECT_EQ(chunk.count, 0u);
}

}  // namespace
}  // namespace parallax
