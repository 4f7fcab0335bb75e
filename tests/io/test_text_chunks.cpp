// Text files read without holding positions as doubles: the quantization chosen from a sample
// and checked after the parse (kept, shifted by whole offsets, or parsed again), the chunk reader
// the octree builder streams text through, and the point count without parsing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/text_decoder.h"
#include "io/text_reader.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

// Large enough (over the 64 Ki points parsed whole) that the quantization comes from a sample.
constexpr int kLines = 70'000;

struct Written {
  std::string text;
  std::vector<std::array<double, 3>> points;  // as strtod reads the written values
};

// `kLines` points "x y z r g b" with `decimals` digits after the point, at UTM-like coordinates;
// `special(i, x, y, z)` may rewrite line i's positions as text.
template <class Special>
Written writeLines(int decimals, Special special) {
  Written out;
  out.text = "x y z r g b\n";
  char line[160];
  for (int i = 0; i < kLines; ++i) {
    char xs[40], ys[40], zs[40];
    std::snprintf(xs, sizeof xs, "%.*f", decimals, 512000.0 + (i % 997) * 0.37);
    std::snprintf(ys, sizeof ys, "%.*f", decimals, 5400000.0 + (i % 991) * 0.53);
    std::snprintf(zs, sizeof zs, "%.*f", decimals, 100.0 + (i % 89) * 0.11);
    std::string x = xs, y = ys, z = zs;
    special(i, x, y, z);
    std::snprintf(line, sizeof line, "%s %s %s %d %d %d\n", x.c_str(), y.c_str(), z.c_str(),
                  i % 256, (i / 3) % 256, 255 - i % 256);
    out.text += line;
    out.points.push_back({std::strtod(x.c_str(), nullptr), std::strtod(y.c_str(), nullptr),
                          std::strtod(z.c_str(), nullptr)});
  }
  return out;
}

PointCloud readXyzText(const std::string& text, bool parallel = true) {
  return readTextFromMemory({reinterpret_cast<const std::byte*>(text.data()), text.size()}, "t.xyz",
                            {.parallel = parallel});
}

// Every written value is a point of the quantization's grid, and the one read: world values
// within a thousandth of a step (the step itself is not a binary fraction, so not to the bit).
void expectExact(const PointCloud& cloud, const Written& written) {
  ASSERT_EQ(cloud.count, written.points.size());
  for (std::size_t i = 0; i < cloud.count; ++i) {
    ASSERT_NEAR(cloud.worldX(i), written.points[i][0], cloud.quantization.scale[0] * 1e-3) << i;
    ASSERT_NEAR(cloud.worldY(i), written.points[i][1], cloud.quantization.scale[1] * 1e-3) << i;
    ASSERT_NEAR(cloud.worldZ(i), written.points[i][2], cloud.quantization.scale[2] * 1e-3) << i;
  }
}

TEST(TextQuantization, SampledDecimalFileIsReadExactlyAtItsResolution) {
  const Written written = writeLines(3, [](int, std::string&, std::string&, std::string&) {});
  for (bool parallel : {true, false}) {
    const PointCloud cloud = readXyzText(written.text, parallel);
    EXPECT_EQ(cloud.quantization.scale, (std::array<double, 3>{0.001, 0.001, 0.001}));
    // The values fit int32 at 1 mm with offset 0 on x and z; y (5.4e9 mm) needs its centre.
    EXPECT_EQ(cloud.quantization.offset[0], 0.0);
    EXPECT_EQ(cloud.quantization.offset[1], std::nearbyint(5400000.0 + 990 * 0.53 / 2));
    EXPECT_EQ(cloud.quantization.offset[2], 0.0);
    expectExact(cloud, written);
    EXPECT_EQ(cloud.colors[1234], (Rgba8{1234 % 256, (1234 / 3) % 256, 255 - 1234 % 256, 255}));
  }
}

TEST(TextQuantization, ALongerDecimalTheSampleMissedIsStillExact) {
  // Two decimals everywhere but one line deep in the file with five: the file's resolution is
  // 10 um on x, whatever the sample saw.
  const Written written = writeLines(2, [](int i, std::string& x, std::string&, std::string&) {
    if (i == 66'666) x = "512001.23456";
  });
  const PointCloud cloud = readXyzText(written.text);
  EXPECT_EQ(cloud.quantization.scale[0], 1e-5);
  EXPECT_EQ(cloud.quantization.scale[1], 0.01);
  expectExact(cloud, written);
}

TEST(TextQuantization, AFarOutlierTheSampleMissedIsStillExact) {
  const Written written = writeLines(3, [](int i, std::string&, std::string&, std::string& z) {
    if (i == 44'444) z = "3000000.125";  // beyond int32 at 1 mm from offset 0
  });
  const PointCloud cloud = readXyzText(written.text);
  expectExact(cloud, written);
  EXPECT_EQ(cloud.bounds.max[2], 3000000.125);
  EXPECT_EQ(cloud.quantization.scale[2], 0.001);
}

TEST(TextQuantization, ExponentsGiveABinaryScaleThatHoldsEveryPoint) {
  const Written written = writeLines(3, [](int i, std::string& x, std::string&, std::string&) {
    if (i % 5 == 0) x = std::to_string(512 + i % 997) + "e3";
  });
  const PointCloud cloud = readXyzText(written.text);
  const double scale = cloud.quantization.scale[0];
  EXPECT_EQ(std::exp2(std::round(std::log2(scale))), scale) << "not a power of two: " << scale;
  // Every point within half a step of what was written.
  for (std::size_t i = 0; i < cloud.count; ++i) {
    ASSERT_LE(std::abs(cloud.worldX(i) - written.points[i][0]), scale / 2) << i;
  }
  EXPECT_EQ(cloud.quantization.scale[1], 0.001);
}

TEST(TextQuantization, PlanRequantizeShiftsOrDecodesAgain) {
  using namespace text;
  PositionStats exact;
  exact.raw.extend(10.0, 20.0, 30.0);
  exact.raw.extend(11.5, 25.25, 31.0);
  exact.decimals[0] = 1;
  exact.decimals[1] = 2;
  exact.decimals[2] = 0;
  // Same scales, other whole offsets: a shift to the exact choice (offset 0 fits here).
  SampledQuantization used;
  used.quantization.scale = {0.1, 0.01, 1.0};
  used.quantization.offset = {11.0, 23.0, 31.0};
  used.decimal[0] = used.decimal[1] = used.decimal[2] = true;
  RequantizePlan plan = planRequantize(used, exact);
  EXPECT_EQ(plan.action, Requantize::Shift);
  EXPECT_EQ(plan.final.offset, (std::array<double, 3>{0.0, 0.0, 0.0}));
  EXPECT_EQ(plan.final.scale, used.quantization.scale);

  PointCloud cloud;
  cloud.count = 1;
  cloud.positions = Column<Int3>(1);
  cloud.quantization = used.quantization;
  cloud.positions[0] = {5, 225, -1};  // 11.5, 25.25, 30
  shiftPositions(cloud, plan.final, false);
  EXPECT_EQ(cloud.positions[0], (Int3{115, 2525, 30}));
  EXPECT_EQ(cloud.worldY(0), 25.25);

  // The sample saw fewer decimals: parsed again.
  used.quantization.scale[1] = 0.1;
  EXPECT_EQ(planRequantize(used, exact).action, Requantize::Decode);
  // A point fell outside: parsed again.
  used.quantization = plan.final;
  exact.outside[2] = true;
  EXPECT_EQ(planRequantize(used, exact).action, Requantize::Decode);
  exact.outside[2] = false;
  EXPECT_EQ(planRequantize(used, exact).action, Requantize::None);
}

std::filesystem::path writeFile(const test::TempDir& dir, const std::string& name,
                                const std::string& text) {
  return dir.write(name, text);
}

TEST(TextChunkReader, ChunksOfAnySizeEqualTheWholeRead) {
  test::TempDir dir;
  const Written written = writeLines(3, [](int i, std::string& x, std::string&, std::string&) {
    if (i == 4321) x = "512002.5";  // fewer decimals: nothing changes
  });
  // Comments and blank lines between the points too.
  std::string text = written.text;
  text.insert(text.find('\n', 5000) + 1, "# a comment\n\n");
  const auto path = writeFile(dir, "scan.xyz", text);
  const PointCloud whole = readText(path);
  for (std::size_t chunk_size :
       {std::size_t(1), std::size_t(777), std::size_t(65536), std::size_t(kLines)}) {
    SCOPED_TRACE(chunk_size);
    if (chunk_size == 1) {
      // One point at a time over the first lines only (the whole file would take a while).
      TextChunkReader reader(path);
      PointCloud chunk;
      for (int i = 0; i < 300; ++i) {
        ASSERT_TRUE(reader.next(chunk, 1));
        ASSERT_EQ(chunk.count, 1u);
        ASSERT_NEAR(chunk.worldX(0), written.points[std::size_t(i)][0], 1e-6) << i;
      }
      continue;
    }
    TextChunkReader reader(path);
    EXPECT_EQ(reader.pointCount(), std::uint64_t(kLines));
    EXPECT_EQ(reader.quantization(), whole.quantization);
    PointCloud chunk;
    std::size_t at = 0;
    while (reader.next(chunk, chunk_size)) {
      ASSERT_LE(chunk.count, chunk_size);
      EXPECT_EQ(chunk.quantization, whole.quantization);
      for (std::size_t i = 0; i < chunk.count; ++i, ++at) {
        ASSERT_EQ(chunk.positions[i], whole.positions[at]) << at;
        ASSERT_EQ(chunk.colors[i], whole.colors[at]) << at;
      }
    }
    EXPECT_EQ(at, std::size_t(kLines));
    EXPECT_EQ(chunk.count, 0u);
  }
}

TEST(TextChunkReader, ExactQuantizationEvenWhereASampleWouldMissALongDecimal) {
  test::TempDir dir;
  const Written written = writeLines(2, [](int i, std::string&, std::string& y, std::string&) {
    if (i == 67'890) y = "5400000.1234";
  });
  const auto path = writeFile(dir, "scan.xyz", written.text);
  TextChunkReader reader(path);
  EXPECT_EQ(reader.quantization().scale[1], 1e-4);
  PointCloud chunk;
  std::size_t at = 0;
  while (reader.next(chunk, 30'000)) {
    for (std::size_t i = 0; i < chunk.count; ++i, ++at) {
      ASSERT_NEAR(chunk.worldY(i), written.points[at][1], 1e-7) << at;
    }
  }
  EXPECT_EQ(at, std::size_t(kLines));
}

TEST(TextChunkReader, ABadLineDeepInTheFileIsNamedWithItsLine) {
  test::TempDir dir;
  Written written = writeLines(3, [](int i, std::string&, std::string&, std::string& z) {
    if (i == 60'000) z = "1.5.5";
  });
  const auto path = writeFile(dir, "scan.xyz", written.text);
  TextChunkReader reader(path);
  PointCloud chunk;
  std::uint64_t delivered = 0;
  try {
    while (reader.next(chunk, 10'000)) delivered += chunk.count;
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().line, 60'002u);  // the header line, then 60 000 lines before it
    EXPECT_EQ(e.info().property, "z");
    EXPECT_EQ(e.info().found, "'1.5.5'");
  }
  EXPECT_EQ(delivered, 60'000u);  // every chunk before the bad line's was delivered
}

TEST(TextChunkReader, AGivenQuantizationThatMissesAPointIsAnError) {
  test::TempDir dir;
  const auto path = writeFile(dir, "small.xyz", "1.5 2.5 3.5\n100000 2 3\n");
  Quantization tight;
  tight.scale = {1e-6, 1e-6, 1e-6};
  TextChunkReader reader(path, {}, &tight);
  PointCloud chunk;
  try {
    reader.next(chunk, 10);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().file, path.string());
    EXPECT_NE(e.info().found.find("outside"), std::string::npos) << e.what();
  }
}

TEST(TextChunkReader, CountsOnlyDataLines) {
  test::TempDir dir;
  const auto xyz = writeFile(dir, "a.xyz", "# comment\nx,y,z\n1,2,3\n\n// more\n4,5,6\n7,8,9\n");
  EXPECT_EQ(countTextPoints(xyz), 3u);
  EXPECT_EQ(TextChunkReader(xyz).pointCount(), 3u);
  const auto pts = writeFile(dir, "b.pts", "2\n1 2 3 4 5 6 7\n1 2 3 4 5 6 7\n1\n1 2 3 4 5 6 7\n");
  EXPECT_EQ(countTextPoints(pts), 3u);
  const Written written = writeLines(1, [](int, std::string&, std::string&, std::string&) {});
  EXPECT_EQ(countTextPoints(writeFile(dir, "big.xyz", written.text)), std::uint64_t(kLines));
  EXPECT_THROW(countTextPoints(writeFile(dir, "bad.xyz", "1 2\n")), InputError);
}

}  // namespace
}  // namespace parallax
