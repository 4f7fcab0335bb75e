// The LAZ file layer on the files LAZ writers leave behind and on damaged ones: variable chunk
// sizes, a chunk table whose offset is at the end of the file, a missing table (recovered by
// decoding in order), and every kind of damage as an InputError that names the file, the place
// and what was wrong; never a crash, a hang or a silent wrong answer.
#include <gtest/gtest.h>

#include <cstring>

#include "core/error.h"
#include "io/las_reader.h"
#include "io/laz/laz_layout.h"
#include "io/laz/pointwise_codec.h"
#include "io/laz_reader.h"
#include "io/laz_test_files.h"
#include "io/laz_writer.h"
#include "support/allocation_counter.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::lazData;

enum class Table { Normal, AtEnd, Missing };

// A LAZ file of the points of point-color-time.las (format 3), assembled here chunk by chunk so
// that each test chooses the layout: the header and VLRs of Parallax's own LAZ output, the
// chunks' point counts, variable or fixed sizes, where the table is.
struct LazBuilder {
  std::string prefix;  // header + VLRs
  std::uint64_t vlr_offset = 0;
  std::vector<laz::LazItem> items;
  std::string records;
  std::size_t length = 0;

  LazBuilder() {
    test::TempDir dir;
    const PointCloud cloud = readLas(lazData("point-color-time.las"));
    writeLaz(cloud, dir / "base.laz");
    writeLas(cloud, dir / "base.las");
    const LasHeader header = readLasHeader(dir / "base.laz");
    prefix = test::fileBytes(dir / "base.laz").substr(0, header.point_data_offset);
    vlr_offset = header.laszip_vlr_offset;
    items = header.laszip->items;
    records = test::lasRecords(dir / "base.las");
    length = header.record_length;
  }
  std::size_t points() const { return records.size() / length; }

  std::string build(const std::vector<std::size_t>& chunk_points, bool variable,
                    Table table = Table::Normal) const {
    std::string file = prefix;
    const std::uint32_t chunk_size = variable ? laz::kVariableChunkSize : chunk_points[0];
    std::memcpy(file.data() + vlr_offset + 12, &chunk_size, 4);
    const std::uint64_t data_start = file.size();
    file.append(8, '\0');
    auto encoder = laz::makePointwiseEncoder(items);
    std::vector<laz::LazChunk> chunks;
    std::size_t first = 0;
    for (std::size_t n : chunk_points) {
      std::vector<std::uint8_t> bytes;
      encoder->encode(reinterpret_cast<const std::byte*>(records.data()) + first * length, n,
                      bytes);
      chunks.push_back({.offset = file.size(), .bytes = bytes.size(), .points = n});
      file.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
      first += n;
    }
    std::uint64_t slot = file.size();
    if (table == Table::Missing) {
      slot = data_start;
    } else {
      const std::uint32_t head[2] = {0, std::uint32_t(chunks.size())};
      file.append(reinterpret_cast<const char*>(head), 8);
      const auto stream = laz::encodeChunkTable(chunks, variable);
      file.append(reinterpret_cast<const char*>(stream.data()), stream.size());
      if (table == Table::AtEnd) {
        file.append(reinterpret_cast<const char*>(&slot), 8);
        slot = ~std::uint64_t(0);
      }
    }
    std::memcpy(file.data() + data_start, &slot, 8);
    return file;
  }
};

PointCloud readBytes(const std::string& bytes) {
  return readLazFromMemory(std::as_bytes(std::span(bytes.data(), bytes.size())), "t.laz");
}

InputErrorInfo errorOf(const std::string& bytes) {
  try {
    readBytes(bytes);
  } catch (const InputError& e) {
    EXPECT_EQ(e.info().file, "t.laz");
    return e.info();
  }
  ADD_FAILURE() << "no error";
  return {};
}

void expectTwin(const PointCloud& cloud) {
  const PointCloud twin = readLas(lazData("point-color-time.las"));
  ASSERT_EQ(cloud.count, twin.count);
  for (std::size_t i = 0; i < twin.count; ++i) {
    ASSERT_EQ(cloud.positions[i], twin.positions[i]) << i;
    ASSERT_EQ(cloud.colors[i], twin.colors[i]) << i;
  }
  EXPECT_EQ(std::memcmp(cloud.findScalar(las_names::kGpsTime)->data.data(),
                        twin.findScalar(las_names::kGpsTime)->data.data(), twin.count * 8),
            0);
}

TEST(LazFile, VariableChunkSizes) {
  const LazBuilder b;
  ASSERT_EQ(b.points(), 1065u);
  expectTwin(readBytes(b.build({100, 1, 600, 64, 300}, true)));
}

TEST(LazFile, ChunkTableOffsetAtTheEnd) {
  const LazBuilder b;
  expectTwin(readBytes(b.build({500, 500, 65}, false, Table::AtEnd)));
  expectTwin(readBytes(b.build({100, 965}, true, Table::AtEnd)));
}

TEST(LazFile, MissingTableOfFixedChunksIsRecoveredInOrder) {
  const LazBuilder b;
  test::TempDir dir;
  const auto path = dir.write("no-table.laz", b.build({300, 300, 300, 165}, false, Table::Missing));
  expectTwin(readLaz(path));
  expectTwin(readLaz(path, {.parallel = false}));
  const LazSummary summary = summarizeLaz(path);
  EXPECT_NE(summary.table_note.find("interrupted"), std::string::npos) << summary.table_note;
  // The stream and the preview find the chunks in order too.
  LazChunkReader reader(path);
  PointCloud chunk;
  std::size_t total = 0;
  while (reader.next(chunk, 400)) total += chunk.count;
  EXPECT_EQ(total, 1065u);
  EXPECT_GT(readLazPreview(path, 400).count, 0u);
}

TEST(LazFile, MissingTableOfVariableChunksIsAClearError) {
  const LazBuilder b;
  const InputErrorInfo e = errorOf(b.build({500, 565}, true, Table::Missing));
  EXPECT_EQ(e.element, "LAZ chunk table");
  EXPECT_NE(e.expected.find("variable sizes"), std::string::npos) << e.expected;
}

TEST(LazFile, LyingChunkTableIsAnError) {
  const LazBuilder b;
  const std::string good = b.build({500, 500, 65}, false);
  const LasHeader header =
      parseLasHeader(std::as_bytes(std::span(good.data(), good.size())), "t.laz");
  std::uint64_t table;
  std::memcpy(&table, good.data() + header.point_data_offset, 8);
  {
    std::string bad = good;  // one chunk more than 1065 points in chunks of 500 make
    const std::uint32_t count = 4;
    std::memcpy(bad.data() + table + 4, &count, 4);
    const InputErrorInfo e = errorOf(bad);
    EXPECT_EQ(e.byte_offset, table + 4);
    EXPECT_NE(e.found.find("4 chunks"), std::string::npos) << e.found;
  }
  {
    std::string bad = good;  // a count no file can hold
    const std::uint32_t count = 0xFFFFFFF0u;
    std::memcpy(bad.data() + table + 4, &count, 4);
    EXPECT_NE(errorOf(bad).expected.find("at most"), std::string::npos);
  }
  {
    // A header's point count far beyond the file: the chunks it would take are counted, not
    // listed (a fuzzed file with 2^31 points in chunks of 16 asked for 2 GB), and named.
    std::string bad = good;
    const std::uint32_t legacy = 4'000'000'000u;
    std::memcpy(bad.data() + 107, &legacy, 4);
    if (header.version_minor >= 4) {
      const std::uint64_t count = legacy;
      std::memcpy(bad.data() + 247, &count, 8);
    }
    test::AllocationScope allocations;  // malloc and mmap counted (allocation_counter.h)
    const InputErrorInfo e = errorOf(bad);
    EXPECT_LT(allocations.bytes(), 1u << 20);
    EXPECT_EQ(e.byte_offset, table + 4);
    EXPECT_NE(e.expected.find("8000000 chunks of 500 points for the header's 4000000000 points"),
              std::string::npos)
        << e.expected;
  }
  {
    // Variable chunks whose counts do not add up to the header's.
    const LazBuilder v;
    std::string bad = v.build({500, 565}, true);
    std::uint32_t legacy = 1066;
    std::memcpy(bad.data() + 107, &legacy, 4);
    const InputErrorInfo e = errorOf(bad);
    EXPECT_NE(e.found.find("1065 points in 2 chunks"), std::string::npos) << e.found;
  }
  {
    // The table offset pointing into the chunks: no table there (its version is not 0), and
    // with chunks of a fixed size they are found by decoding them in order, correctly.
    std::string bad = good;
    const std::uint64_t wrong = header.point_data_offset + 100;
    std::memcpy(bad.data() + header.point_data_offset, &wrong, 8);
    expectTwin(readBytes(bad));
  }
}

TEST(LazFile, CorruptOrTruncatedChunksNameTheChunk) {
  const LazBuilder b;
  const std::string good = b.build({400, 400, 265}, false);
  const LasHeader header =
      parseLasHeader(std::as_bytes(std::span(good.data(), good.size())), "t.laz");
  std::uint64_t table;
  std::memcpy(&table, good.data() + header.point_data_offset, 8);
  std::string bad = good;
  const std::size_t middle =
      std::size_t(header.point_data_offset + 8 + (table - 8 - header.point_data_offset) / 2);
  for (std::size_t i = middle; i < middle + 40; ++i) bad[i] = char(~bad[i]);
  const InputErrorInfo e = errorOf(bad);
  EXPECT_NE(e.element.find("LAZ chunk 2 of 3 (points 400-799)"), std::string::npos) << e.element;
  EXPECT_NE(e.found.find("first point affected: 400"), std::string::npos) << e.found;
  // Truncated anywhere: an error, never a crash.
  for (std::size_t cut = header.point_data_offset; cut < good.size(); cut += 97) {
    EXPECT_THROW(readBytes(good.substr(0, cut)), InputError) << cut;
  }
  // Cut inside the last chunk (the chunk table gone with the end): the chunk's size is unknown,
  // so the message says what it read, not "in 0 bytes", and that the file is truncated.
  const InputErrorInfo cut = errorOf(good.substr(0, std::size_t(table) - 10));
  EXPECT_NE(cut.element.find("LAZ chunk 3 of 3"), std::string::npos) << cut.element;
  EXPECT_EQ(cut.expected.find(" in 0 bytes"), std::string::npos) << cut.expected;
  EXPECT_NE(cut.expected.find("its size unknown without the chunk table"), std::string::npos)
      << cut.expected;
  EXPECT_NE(cut.hint.find("truncated"), std::string::npos) << cut.hint;
}

TEST(LazFile, UnknownCompressorCoderOrItemIsRefused) {
  const LazBuilder b;
  const std::string good = b.build({1065}, false);
  auto patch16 = [&](std::size_t offset, std::uint16_t value) {
    std::string bad = good;
    std::memcpy(bad.data() + b.vlr_offset + offset, &value, 2);
    return bad;
  };
  EXPECT_NE(errorOf(patch16(0, 7)).found.find("compressor 7"), std::string::npos);
  EXPECT_NE(errorOf(patch16(0, 0)).hint.find("not compressed"), std::string::npos);
  EXPECT_NE(errorOf(patch16(2, 1)).found.find("coder 1"), std::string::npos);
  // Item 1's type (34 + 0), item 2's version (34 + 6 + 4).
  EXPECT_NE(errorOf(patch16(34, 99)).found.find("type 99"), std::string::npos);
  const InputErrorInfo version = errorOf(patch16(44, 3));
  EXPECT_NE(version.found.find("GPSTIME11"), std::string::npos) << version.found;
  EXPECT_NE(version.found.find("versions 1 and 2"), std::string::npos) << version.found;
  // A layered item in a point-wise file.
  EXPECT_NE(errorOf(patch16(34, 10)).found.find("layered"), std::string::npos);
}

}  // namespace
}  // namespace parallax
