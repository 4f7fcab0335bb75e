// Selective reading wired through the readers: readLaz and LazChunkReader (the COPC reader: in
// tests/lod/test_copc_selective.cpp), asked for some attributes (core/attribute_selection.h),
// give exactly a full read's values for those columns and leave the others out, on every LAZ file of PARALLAX_TEST_DATA/laz (layered and
// point-wise) and on layered files Parallax writes itself (formats 7 and 8 from real records).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/attribute_selection.h"
#include "io/las_header.h"
#include "io/laz_reader.h"
#include "io/point_file.h"
#include "support/selected_columns.h"
#include "support/test_data.h"

namespace parallax {
namespace {

using test::expectSelected;
using test::selections;

// Concatenates every batch of a LazChunkReader (odd batch sizes, so batches end inside chunks).
PointCloud readInBatches(const std::filesystem::path& path, const AttributeSelection& selection) {
  LazChunkReader reader(path, selection);
  std::vector<PointCloud> batches;
  PointCloud batch;
  while (reader.next(batch, 7777)) batches.push_back(std::move(batch));
  PointCloud all = readLaz(path, {.attributes = selection});  // the shape, then overwritten
  std::size_t at = 0;
  for (const PointCloud& b : batches) {
    std::memcpy(all.positions.data() + at, b.positions.data(), b.count * sizeof(Int3));
    if (b.hasColors()) {
      std::memcpy(all.colors.data() + at, b.colors.data(), b.count * sizeof(Rgba8));
      std::memcpy(all.stored_colors.data() + at, b.stored_colors.data(), b.count * sizeof(Rgb16));
    } else {
      EXPECT_FALSE(all.hasColors());
    }
    if (b.hasIntensity()) std::memcpy(all.intensity.data() + at, b.intensity.data(), b.count * 4);
    if (b.hasClassification()) {
      std::memcpy(all.classification.data() + at, b.classification.data(), b.count);
    }
    EXPECT_EQ(b.hasIntensity(), all.hasIntensity());
    EXPECT_EQ(b.hasClassification(), all.hasClassification());
    EXPECT_EQ(b.scalars.size(), all.scalars.size());
    for (std::size_t s = 0; s < b.scalars.size() && s < all.scalars.size(); ++s) {
      const std::size_t size = scalarSize(b.scalars[s].type);
      std::memcpy(all.scalars[s].data.data() + at * size, b.scalars[s].data.data(), b.count * size);
    }
    at += b.count;
  }
  EXPECT_EQ(at, all.count);
  return all;
}

void checkLazFile(const std::filesystem::path& path, const std::string& what) {
  const PointCloud full = readLaz(path);
  ASSERT_GT(full.count, 0u) << what;
  for (const AttributeSelection& selection : selections()) {
    expectSelected(full, readLaz(path, {.attributes = selection}), selection, what + " readLaz");
    expectSelected(full, readLaz(path, {.parallel = false, .attributes = selection}), selection,
                   what + " readLaz on one thread");
    expectSelected(full, readPointFile(path, {.attributes = selection}), selection,
                   what + " readPointFile");
    PointCloud batches = readInBatches(path, selection);
    batches.bounds = full.bounds;  // a concatenation has no bounds of its own
    expectSelected(full, batches, selection, what + " LazChunkReader");
  }
}

TEST(LazSelectiveReaders, EveryTestFileGivesTheAskedColumnsOfAFullRead) {
  for (const char* name :
       {"point-time-1.4.las.laz", "ellipsoid.laz", "ellipsoid.copc.laz", "simple.copc.laz",
        "point10.las.laz", "point-color-time.las.laz", "point-color.las.laz", "point-time.las.laz",
        "extrabytes.laz", "1815.laz"}) {
    checkLazFile(test::testDataFile(std::string("laz/") + name), name);
  }
}

TEST(LazSelectiveReaders, ParallaxsOwnLayeredFilesGiveTheAskedColumns) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("parallax-laz-selective-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  // Real records (colour, GPS time; extra bytes with descriptions) written as formats 6, 7 and 8
  // (6 without colour, 8 adds a NIR column of zeros) in small chunks, so that every reader meets
  // many chunks.
  for (const auto& [source, format] :
       std::vector<std::pair<std::string, int>>{{"point-time.las.laz", 6},
                                                {"point-color-time.las.laz", 7},
                                                {"point-color-time.las.laz", 8},
                                                {"extrabytes.laz", 7}}) {
    const std::filesystem::path in = test::testDataFile("laz/" + source);
    const std::filesystem::path out = dir / (source + "." + std::to_string(format) + ".laz");
    writePointFile(readLaz(in), out,
                   {.las_point_format = format, .laz_chunk_points = 333, .source = in});
    ASSERT_EQ(readLasHeader(out).point_format, format);
    checkLazFile(out, out.filename().string());
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace parallax
