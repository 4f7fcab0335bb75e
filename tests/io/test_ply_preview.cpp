#include "io/ply_preview.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "core/error.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

// Point i sits at (i, 2i, -i) with colour i % 256: a point of the preview tells which record it
// came from.
void writeNumberedPly(const std::filesystem::path& path, int count, bool ascii) {
  std::ofstream out(path, std::ios::binary);
  out << "ply\nformat " << (ascii ? "ascii" : "binary_little_endian") << " 1.0\n"
      << "element vertex " << count << "\n"
      << "property float x\nproperty float y\nproperty float z\nproperty uchar red\n"
      << "property uchar green\nproperty uchar blue\nelement face 1\n"
      << "property list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < count; ++i) {
    const float xyz[3] = {float(i), float(2 * i), float(-i)};
    const unsigned char rgb[3] = {(unsigned char)(i % 256), 7, 9};
    if (ascii) {
      out << i << ' ' << 2 * i << ' ' << -i << ' ' << i % 256 << " 7 9\n";
    } else {
      out.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
      out.write(reinterpret_cast<const char*>(rgb), sizeof rgb);
    }
  }
  if (ascii) {
    out << "3 0 1 2\n";
  } else {
    const unsigned char n = 3;
    const int indices[3] = {0, 1, 2};
    out.write(reinterpret_cast<const char*>(&n), 1);
    out.write(reinterpret_cast<const char*>(indices), sizeof indices);
  }
}

// Every preview point is an unchanged record; records come in file order and cover the whole
// file (the last one sits in the last tenth).
void expectSpreadSubset(const PointCloud& preview, int count) {
  ASSERT_GT(preview.count, 0u);
  long previous = -1;
  for (std::size_t i = 0; i < preview.count; ++i) {
    const double x = preview.worldX(i);
    const long record = long(x);
    ASSERT_EQ(double(record), x);
    ASSERT_GT(record, previous) << "point " << i;
    ASSERT_LT(record, count);
    EXPECT_EQ(preview.worldY(i), 2.0 * x);
    EXPECT_EQ(preview.worldZ(i), -x);
    EXPECT_EQ(preview.colors[i], (Rgba8{std::uint8_t(record % 256), 7, 9, 255}));
    previous = record;
  }
  EXPECT_GT(previous, count - count / 10);
}

TEST(PlyPreview, BinarySampleIsEvenRunsOfExactRecords) {
  test::TempDir dir;
  writeNumberedPly(dir / "big.ply", 100000, false);
  PointCloud preview = readPlyPreview(dir / "big.ply", 6400);
  EXPECT_GE(preview.count, 6400u);
  EXPECT_LE(preview.count, 6400u + 64u);
  expectSpreadSubset(preview, 100000);
}

TEST(PlyPreview, AsciiSampleIsEvenRunsOfExactRecords) {
  test::TempDir dir;
  writeNumberedPly(dir / "big.ply", 50000, true);
  PointCloud preview = readPlyPreview(dir / "big.ply", 3200);
  EXPECT_GE(preview.count, 3000u);
  EXPECT_LE(preview.count, 3200u + 64u);
  expectSpreadSubset(preview, 50000);
}

TEST(PlyPreview, SmallFileIsReadWhole) {
  test::TempDir dir;
  writeNumberedPly(dir / "small.ply", 500, false);
  PointCloud preview = readPlyPreview(dir / "small.ply", 1000);
  ASSERT_EQ(preview.count, 500u);
  expectSpreadSubset(preview, 500);
}

TEST(PlyPreview, TruncatedFileIsAnInputError) {
  test::TempDir dir;
  writeNumberedPly(dir / "cut.ply", 100000, false);
  std::filesystem::resize_file(dir / "cut.ply", 50000);
  EXPECT_THROW(readPlyPreview(dir / "cut.ply", 6400), InputError);
}

}  // namespace
}  // namespace parallax
