// LAS and LAZ records kept through `parallax convert`, checked against the source's bytes parsed
// here, independently of Parallax's LAS header reader (LAS 1.4 R15, tables 3, 4 and 5): the
// header's identifying fields, every VLR and EVLR, the records of the points a --clip-box keeps
// (16-bit colours as stored), and the message when a forced point format drops a field.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/laz_test_files.h"
#include "support/run_parallax.h"

namespace parallax {
namespace {

using test::lazData;
using test::quoted;

template <class T>
T get(const std::string& bytes, std::size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof value);
  return value;
}
template <class T>
void put(std::string& bytes, std::size_t at, T value) {
  std::memcpy(bytes.data() + at, &value, sizeof value);
}

struct Record {  // a VLR or an EVLR
  std::string user_id, description, payload;
  std::uint16_t id = 0;
  friend bool operator==(const Record&, const Record&) = default;
};

struct RawLas {
  std::string identity;  // file source id, global encoding, GUID, version, system identifier,
                         // generating software, creation day and year (bytes 4-93)
  int point_format = 0;  // without LASzip's bits
  std::size_t record_length = 0;
  std::vector<Record> vlrs, evlrs;  // without LASzip's VLR
  std::string records;              // the point records (LAS files only)
};

std::string trimmed(const std::string& bytes, std::size_t at, std::size_t size) {
  std::string text = bytes.substr(at, size);
  return text.substr(0, text.find('\0'));
}

RawLas parseRaw(const std::filesystem::path& path) {
  const std::string b = test::fileBytes(path);
  EXPECT_EQ(b.substr(0, 4), "LASF") << path;
  RawLas las;
  las.identity = b.substr(4, 90);
  const auto header_size = get<std::uint16_t>(b, 94);
  const auto data_offset = get<std::uint32_t>(b, 96);
  const auto vlr_count = get<std::uint32_t>(b, 100);
  las.point_format = get<std::uint8_t>(b, 104) & 0x3F;
  las.record_length = get<std::uint16_t>(b, 105);
  std::size_t at = header_size;
  for (std::uint32_t i = 0; i < vlr_count; ++i) {
    Record r{trimmed(b, at + 2, 16), trimmed(b, at + 22, 32), "", get<std::uint16_t>(b, at + 18)};
    const auto length = get<std::uint16_t>(b, at + 20);
    r.payload = b.substr(at + 54, length);
    at += 54 + length;
    if (r.user_id != "laszip encoded") las.vlrs.push_back(r);
  }
  std::uint64_t points = get<std::uint32_t>(b, 107);
  if (b[25] >= 4) {  // LAS 1.4: the EVLRs and the 64-bit count
    points = get<std::uint64_t>(b, 247);
    std::uint64_t evlr = get<std::uint64_t>(b, 235);
    for (std::uint32_t i = 0, n = get<std::uint32_t>(b, 243); i < n; ++i) {
      Record r{trimmed(b, evlr + 2, 16), trimmed(b, evlr + 28, 32), "",
               get<std::uint16_t>(b, evlr + 18)};
      const auto length = get<std::uint64_t>(b, evlr + 20);
      r.payload = b.substr(evlr + 60, length);
      evlr += 60 + length;
      las.evlrs.push_back(r);
    }
  }
  if (!(get<std::uint8_t>(b, 104) & 0xC0)) {
    las.records = b.substr(data_offset, points * las.record_length);
  }
  return las;
}

void expectSameHeader(const RawLas& out, const RawLas& source, const std::string& what) {
  EXPECT_EQ(out.identity, source.identity) << what << ": header fields (bytes 4-93)";
  EXPECT_EQ(out.point_format, source.point_format) << what;
  EXPECT_EQ(out.record_length, source.record_length) << what;
  EXPECT_EQ(out.vlrs, source.vlrs) << what;
  EXPECT_EQ(out.evlrs, source.evlrs) << what;
}

void convert(const test::TempDir& dir, const std::filesystem::path& in,
             const std::filesystem::path& out, const std::string& options = "") {
  const auto run = test::runParallax(
      dir, "convert " + quoted(in.string()) + " -o " + quoted(out.string()) + " -q " + options);
  ASSERT_EQ(run.exit_code, 0) << in << " -> " << out << ": " << run.err;
}

TEST(LasRecordsCli, LazHeaderVlrsAndEvlrsTravelThroughConvert) {
  test::TempDir dir;
  const std::filesystem::path laz = lazData("point-time-1.4.las.laz");
  const RawLas original = parseRaw(laz);
  ASSERT_EQ(original.vlrs.size(), 2u);  // two WKT records (and LASzip's)
  convert(dir, laz, dir / "a.las");
  expectSameHeader(parseRaw(dir / "a.las"), original, "LAZ -> LAS");
  convert(dir, laz, dir / "a.laz");
  expectSameHeader(parseRaw(dir / "a.laz"), original, "LAZ -> LAZ");
  EXPECT_EQ(test::lazRecords(dir / "a.laz"), parseRaw(dir / "a.las").records);

  // The source's GUID, system identifier and file source id are zeros and it has no EVLR: give
  // it values and a vendor EVLR (bytes that mean nothing to Parallax), then LAS -> LAZ -> LAZ ->
  // LAS must keep them all.
  std::string bytes = test::fileBytes(dir / "a.las");
  put<std::uint16_t>(bytes, 4, 4242);
  for (int i = 0; i < 16; ++i) bytes[8 + i] = char(i + 1);
  std::memcpy(bytes.data() + 26, "a test system", 13);
  std::string evlr(60, '\0');
  std::memcpy(evlr.data() + 2, "vendor records", 14);
  put<std::uint16_t>(evlr, 18, 77);
  std::string payload;
  for (int i = 0; i < 300; ++i) payload += char(i * 7);
  put<std::uint64_t>(evlr, 20, payload.size());
  std::memcpy(evlr.data() + 28, "kept as it is", 13);
  put<std::uint64_t>(bytes, 235, bytes.size());
  put<std::uint32_t>(bytes, 243, 1);
  bytes += evlr + payload;
  std::ofstream(dir / "source.las", std::ios::binary) << bytes;
  const RawLas source = parseRaw(dir / "source.las");
  ASSERT_EQ(source.evlrs.size(), 1u);
  convert(dir, dir / "source.las", dir / "b.laz");
  convert(dir, dir / "b.laz", dir / "c.laz", "--laz-chunk 100");
  convert(dir, dir / "c.laz", dir / "d.las");
  expectSameHeader(parseRaw(dir / "b.laz"), source, "LAS -> LAZ");
  expectSameHeader(parseRaw(dir / "c.laz"), source, "LAZ -> LAZ");
  const RawLas back = parseRaw(dir / "d.las");
  expectSameHeader(back, source, "LAS -> LAZ -> LAZ -> LAS");
  EXPECT_EQ(back.records, source.records);
  EXPECT_EQ(test::lazRecords(dir / "c.laz"), source.records);
}

TEST(LasRecordsCli, ClipBoxKeepsSixteenBitColoursAsStored) {
  test::TempDir dir;
  // point-color.las (format 2) with 16-bit colours none of which is a multiple of 257.
  std::string bytes = test::fileBytes(lazData("point-color.las"));
  const auto data_offset = get<std::uint32_t>(bytes, 96);
  const auto length = get<std::uint16_t>(bytes, 105);
  const auto count = get<std::uint32_t>(bytes, 107);
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::size_t at = data_offset + std::size_t(i) * length + 20;
    put<std::uint16_t>(bytes, at, std::uint16_t(1000 + 61 * i));
    put<std::uint16_t>(bytes, at + 2, std::uint16_t(65534 - 13 * i));
    put<std::uint16_t>(bytes, at + 4, std::uint16_t(300 + 7 * i));
  }
  std::ofstream(dir / "source.las", std::ios::binary) << bytes;
  const RawLas source = parseRaw(dir / "source.las");
  // A box over the west half (world x = X * scale + offset, from the header).
  const double scale_x = get<double>(bytes, 131), offset_x = get<double>(bytes, 155);
  const double max_x = 494500.0;
  std::string kept;
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::string record = source.records.substr(std::size_t(i) * length, length);
    if (get<std::int32_t>(record, 0) * scale_x + offset_x <= max_x) kept += record;
  }
  ASSERT_GT(kept.size(), 100u * length);
  ASSERT_LT(kept.size(), source.records.size());
  const std::string box = "--clip-box 0,0,-1000," + std::to_string(max_x) + ",1e8,1000";
  convert(dir, dir / "source.las", dir / "clip.las", box);
  convert(dir, dir / "source.las", dir / "clip.laz", box);
  convert(dir, dir / "clip.laz", dir / "back.las");
  EXPECT_EQ(parseRaw(dir / "clip.las").records, kept);
  EXPECT_EQ(test::lazRecords(dir / "clip.laz"), kept);
  EXPECT_EQ(parseRaw(dir / "back.las").records, kept);
}

TEST(LasRecordsCli, AForcedFormatNamesTheFieldItDrops) {
  test::TempDir dir;
  const std::filesystem::path source = lazData("point-color-time.las.laz");
  const auto run =
      test::runParallax(dir, "convert " + quoted(source.string()) + " -o " +
                                 quoted((dir / "f1.las").string()) + " --point-format 1");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("dropped or changed: red, green, blue (point format 1 has no colour)"),
            std::string::npos)
      << run.err;
  EXPECT_EQ(parseRaw(dir / "f1.las").point_format, 1);
  // The other way: a format with colour asked for a source without: black colours, every other
  // byte of the records kept (this crashed the writer).
  const std::filesystem::path plain = lazData("1815.las");
  convert(dir, plain, dir / "f3.las", "--point-format 3");
  const RawLas in = parseRaw(plain), out = parseRaw(dir / "f3.las");
  ASSERT_EQ(in.point_format, 1);
  ASSERT_EQ(out.point_format, 3);
  ASSERT_EQ(out.record_length, in.record_length + 6);
  const std::size_t points = in.records.size() / in.record_length;
  ASSERT_EQ(out.records.size(), points * out.record_length);
  for (std::size_t i = 0; i < points; ++i) {
    const std::string a = in.records.substr(i * in.record_length, in.record_length);
    const std::string b = out.records.substr(i * out.record_length, out.record_length);
    ASSERT_EQ(b.substr(0, 28), a.substr(0, 28)) << "point " << i;
    ASSERT_EQ(b.substr(28, 6), std::string(6, '\0')) << "point " << i;
    ASSERT_EQ(b.substr(34), a.substr(28)) << "point " << i;
  }
}

}  // namespace
}  // namespace parallax
