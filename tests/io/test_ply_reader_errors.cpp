// Malformed PLY input: every case throws InputError whose message names the file, where in it
// (header or body line, or byte offset), the element and property, what was expected and what
// was found. Sizes are checked before anything is allocated, so absurd counts fail fast.
#include <gtest/gtest.h>

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <string>
#include <string_view>

#include "io/ply_reader.h"
#include "io/ply_test_files.h"
#include "support/allocation_counter.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::asBytes;
using test::catchInputError;
using test::CaughtInputError;
using test::expectExpectedAndFound;
using test::expectMessageHas;
using test::PlyBody;
using test::plyHeader;

constexpr const char* kName = "broken_scan.ply";

// "Fails fast" is measured in bytes allocated, not seconds (which depend on the machine's load
// and a sanitizer's slowdown): an input of a few hundred bytes whose counts promise terabytes may
// cost its header's strings and the message, never memory sized by the counts. (A loop over a
// lying count would hang instead, and ctest's timeout fails it.)
constexpr std::uint64_t kFailFastBytes = 1 << 20;

CaughtInputError readError(const std::string& bytes, bool parallel = true) {
  PlyReadOptions options;
  options.parallel = parallel;
  return catchInputError([&] { readPlyFromMemory(asBytes(bytes), kName, options); });
}

CaughtInputError headerError(const std::string& bytes) {
  return catchInputError([&] { parsePlyHeader(asBytes(bytes), kName); });
}

// The message shows no raw control or non-ASCII byte (binary input is quoted and escaped).
void expectPrintable(const CaughtInputError& caught) {
  for (char c : caught.message) {
    auto byte = static_cast<unsigned char>(c);
    EXPECT_TRUE(byte >= 0x20 && byte < 0x7f) << "raw byte " << int(byte) << " in message";
  }
}

const std::initializer_list<std::string_view> kXyz = {"element vertex 2", "property float x",
                                                      "property float y", "property float z"};

// An ascii file of two x y z points: its 7-line header puts the body's first line at line 8.
std::string asciiXyz(const std::string& body) {
  return plyHeader(PlyFormat::Ascii, kXyz) + body;
}

// ---------------------------------------------------------------------------------------------
// Header

TEST(PlyReaderErrors, WrongMagic) {
  CaughtInputError caught = readError("plx\nformat ascii 1.0\nelement vertex 0\nend_header\n");
  expectMessageHas(caught, {kName, "line 1", "plx"});
  expectExpectedAndFound(caught);
  EXPECT_NE(caught.info.expected.find("ply"), std::string::npos) << caught.message;
}

TEST(PlyReaderErrors, BinaryGarbageIsQuotedSafely) {
  std::string garbage("\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR", 16);
  CaughtInputError caught = readError(garbage);
  expectMessageHas(caught, {kName});
  expectExpectedAndFound(caught);
  expectPrintable(caught);
}

TEST(PlyReaderErrors, EmptyFile) {
  CaughtInputError caught = readError("");
  expectMessageHas(caught, {kName});
  EXPECT_FALSE(caught.info.expected.empty()) << caught.message;
  EXPECT_NE(caught.info.expected.find("ply"), std::string::npos) << caught.message;
}

TEST(PlyReaderErrors, UnknownFormat) {
  CaughtInputError caught =
      readError("ply\nformat binary_middle_endian 1.0\nelement vertex 0\nend_header\n");
  expectMessageHas(caught, {kName, "line 2", "binary_middle_endian"});
  expectExpectedAndFound(caught);
  EXPECT_NE(caught.info.expected.find("ascii"), std::string::npos)
      << "the message should list the formats: " << caught.message;
}

TEST(PlyReaderErrors, MissingFormatLine) {
  CaughtInputError caught = readError("ply\nelement vertex 0\nend_header\n");
  expectMessageHas(caught, {kName, "format"});
  expectExpectedAndFound(caught);
  // Where the format line should be (line 2) or where its absence is certain (end_header).
  EXPECT_TRUE(caught.message.find("line 2") != std::string::npos ||
              caught.message.find("line 3") != std::string::npos)
      << caught.message;
}

TEST(PlyReaderErrors, UnsupportedVersion) {
  CaughtInputError caught = readError("ply\nformat ascii 2.0\nelement vertex 0\nend_header\n");
  expectMessageHas(caught, {kName, "line 2", "2.0"});
  expectExpectedAndFound(caught);
  EXPECT_NE(caught.info.expected.find("1.0"), std::string::npos) << caught.message;
}

TEST(PlyReaderErrors, UnknownTypeName) {
  CaughtInputError caught =
      readError(plyHeader(PlyFormat::BinaryLittleEndian,
                          {"element vertex 1", "property float x", "property float128 y"}));
  expectMessageHas(caught, {kName, "line 5", "float128", "element 'vertex'"});
  expectExpectedAndFound(caught);
}

TEST(PlyReaderErrors, UnknownListCountType) {
  CaughtInputError caught = readError(plyHeader(
      PlyFormat::BinaryLittleEndian, {"element vertex 1", "property float x", "element face 1",
                                      "property list ulong int vertex_indices"}));
  expectMessageHas(caught, {kName, "line 6", "ulong", "element 'face'"});
  expectExpectedAndFound(caught);
}

TEST(PlyReaderErrors, PropertyBeforeAnyElement) {
  CaughtInputError caught =
      readError(plyHeader(PlyFormat::Ascii, {"property float x", "element vertex 1"}));
  expectMessageHas(caught, {kName, "line 3"});
  expectExpectedAndFound(caught);
  EXPECT_NE(caught.message.find("element"), std::string::npos) << caught.message;
}

TEST(PlyReaderErrors, MalformedElementCounts) {
  for (std::string count : {"-5", "abc", "12x", "99999999999999999999999", ""}) {
    SCOPED_TRACE(count);
    std::string element = "element vertex " + count;
    CaughtInputError caught =
        readError(plyHeader(PlyFormat::BinaryLittleEndian, {element, "property float x"}));
    expectMessageHas(caught, {kName, "line 3", count.empty() ? "vertex" : "element 'vertex'"});
    expectExpectedAndFound(caught);
    if (!count.empty()) {
      EXPECT_NE(caught.info.found.find(count.substr(0, 20)), std::string::npos) << caught.message;
    }
  }
}

TEST(PlyReaderErrors, UnknownKeywordInHeader) {
  CaughtInputError caught =
      readError(plyHeader(PlyFormat::Ascii, {"element vertex 1", "propery float x"}));
  expectMessageHas(caught, {kName, "line 4", "propery"});
  expectExpectedAndFound(caught);
}

TEST(PlyReaderErrors, MalformedPropertyLines) {
  for (std::string line :
       {"property float", "property list uchar int", "property list uchar", "property"}) {
    SCOPED_TRACE(line);
    CaughtInputError caught = readError(
        plyHeader(PlyFormat::BinaryLittleEndian, {"element vertex 1", "property float x", line}));
    expectMessageHas(caught, {kName, "line 5"});
    expectExpectedAndFound(caught);
  }
}

TEST(PlyReaderErrors, MissingEndHeader) {
  CaughtInputError caught =
      readError("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n1\n2\n");
  expectMessageHas(caught, {kName, "end_header"});
  EXPECT_FALSE(caught.info.expected.empty()) << caught.message;
}

TEST(PlyReaderErrors, HeaderLargerThanTheLimitFailsFast) {
  std::string text = "ply\nformat binary_little_endian 1.0\nelement vertex 1\n";
  std::string comment = "comment " + std::string(90, 'c') + "\n";
  // Sixteen times the limit: a reader that went on past the limit would hold all of it.
  while (text.size() < 16 * kMaxPlyHeaderBytes) text += comment;
  text += "property float x\nend_header\n";
  text += std::string(4, '\0');
  test::AllocationScope allocations;
  CaughtInputError caught = readError(text);
  EXPECT_LT(allocations.bytes(), 4 * kMaxPlyHeaderBytes);
  expectMessageHas(caught, {kName, "header"});
  EXPECT_FALSE(caught.info.expected.empty()) << caught.message;
}

TEST(PlyReaderErrors, ParsePlyHeaderReportsTheSameErrors) {
  CaughtInputError caught =
      headerError("ply\nformat ascii 1.0\nelement vertex 1\nproperty floot x\nend_header\n");
  expectMessageHas(caught, {kName, "line 4", "floot"});
  expectExpectedAndFound(caught);
}

TEST(PlyReaderErrors, NoVertexElement) {
  std::string file =
      plyHeader(PlyFormat::Ascii, {"element face 1", "property list uchar int vertex_indices"}) +
      "3 0 1 2\n";
  CaughtInputError caught = readError(file);
  expectMessageHas(caught, {kName, "vertex"});
  EXPECT_FALSE(caught.info.expected.empty()) << caught.message;
}

TEST(PlyReaderErrors, VertexElementWithoutPositions) {
  std::string file =
      plyHeader(PlyFormat::Ascii, {"element vertex 1", "property float x", "property float y"}) +
      "1 2\n";
  CaughtInputError caught = readError(file);
  expectMessageHas(caught, {kName, "element 'vertex'", "z"});
}

TEST(PlyReaderErrors, PositionDeclaredAsAList) {
  std::string file = plyHeader(
      PlyFormat::BinaryLittleEndian,
      {"element vertex 1", "property float x", "property list uchar float y", "property float z"});
  CaughtInputError caught = readError(file + std::string(13, '\0'));
  expectMessageHas(caught, {kName, "element 'vertex'", "y"});
}

// Assumption (not in the headers): positions must be finite, since they are quantized to int32.
TEST(PlyReaderErrors, NonFinitePosition) {
  CaughtInputError ascii = readError(asciiXyz("1 2 3\n4 nan 6\n"));
  expectMessageHas(ascii, {kName, "line 9", "element 'vertex'", "property 'y'"});
  std::string header = plyHeader(PlyFormat::BinaryLittleEndian, kXyz);
  PlyBody body(PlyFormat::BinaryLittleEndian);
  body.put(1.0f).put(2.0f).put(3.0f).put(std::numeric_limits<float>::infinity()).put(5.0f);
  body.put(6.0f);
  CaughtInputError binary = readError(header + body.bytes());
  expectMessageHas(binary, {kName, "element 'vertex'", "property 'x'"});
}

TEST(PlyReaderErrors, MissingFile) {
  test::TempDir dir;
  auto path = dir / "does_not_exist.ply";
  CaughtInputError caught = catchInputError([&] { readPly(path); });
  expectMessageHas(caught, {"does_not_exist.ply"});
  CaughtInputError chunked = catchInputError([&] { PlyChunkReader reader(path); });
  expectMessageHas(chunked, {"does_not_exist.ply"});
}

TEST(PlyReaderErrors, ReadPlyNamesTheFileOnDisk) {
  test::TempDir dir;
  auto path = dir.write("on_disk.ply", "ply\nformat ascii 9.9\nend_header\n");
  CaughtInputError caught = catchInputError([&] { readPly(path); });
  expectMessageHas(caught, {"on_disk.ply", "line 2", "9.9"});
}

// ---------------------------------------------------------------------------------------------
// Binary body

// A file of two x y z points whose header claims `vertex_count` of them.
std::string twoPointsClaiming(PlyFormat format, const std::string& vertex_count) {
  std::string file = plyHeader(format, {"element vertex " + vertex_count, "property float x",
                                        "property float y", "property float z"});
  PlyBody body(format);
  body.put(1.0f).put(2.0f).put(3.0f).end().put(4.0f).put(5.0f).put(6.0f).end();
  return file + body.bytes();
}

TEST(PlyReaderErrors, CountLargerThanTheFileCanHoldFailsFastWithoutAllocating) {
  for (PlyFormat format : test::kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    const std::string file = twoPointsClaiming(format, "1000000000000");
    test::AllocationScope allocations;
    CaughtInputError caught = readError(file);
    EXPECT_LT(allocations.bytes(), kFailFastBytes);
    expectMessageHas(caught, {kName, "element 'vertex'"});
    expectExpectedAndFound(caught);
  }
}

// A count a file could plausibly hold (10 M points: 120 MB of columns, which the columns would
// take with mmap, unseen by a counter of operator new alone) in a file of two points: the error
// comes before any column is allocated.
TEST(PlyReaderErrors, PlausibleCountBeyondTheFileAllocatesNoColumns) {
  for (PlyFormat format : test::kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    const std::string file = twoPointsClaiming(format, "10000000");
    test::AllocationScope allocations;
    CaughtInputError caught = readError(file);
    EXPECT_LT(allocations.bytes(), kFailFastBytes);
    EXPECT_LT(allocations.largest(), kFailFastBytes);
    expectMessageHas(caught, {kName, "element 'vertex'"});
  }
}

TEST(PlyReaderErrors, HugeCountWithListsFailsFast) {
  std::string file =
      plyHeader(PlyFormat::BinaryLittleEndian,
                {"element vertex 4000000000000", "property float x", "property float y",
                 "property float z", "property list uchar int ids"});
  PlyBody body(PlyFormat::BinaryLittleEndian);
  body.put(1.0f).put(2.0f).put(3.0f).put<std::uint8_t>(0);
  test::AllocationScope allocations;
  CaughtInputError caught = readError(file + body.bytes());
  EXPECT_LT(allocations.bytes(), kFailFastBytes);
  expectMessageHas(caught, {kName, "element 'vertex'"});
}

TEST(PlyReaderErrors, HugeCountOfAnElementBeforeTheVertices) {
  std::string file =
      plyHeader(PlyFormat::BinaryBigEndian,
                {"element face 1000000000000", "property list uchar int vertex_indices",
                 "element vertex 1", "property float x", "property float y", "property float z"});
  test::AllocationScope allocations;
  CaughtInputError caught = readError(file + std::string(40, '\0'));
  EXPECT_LT(allocations.bytes(), kFailFastBytes);
  expectMessageHas(caught, {kName, "element 'face'"});

  std::string ascii =
      plyHeader(PlyFormat::Ascii,
                {"element face 1000000000000", "property list uchar int vertex_indices",
                 "element vertex 1", "property float x", "property float y", "property float z"});
  test::AllocationScope ascii_allocations;
  CaughtInputError caught_ascii = readError(ascii + "3 0 1 2\n3 1 2 3\n1 2 3\n");
  EXPECT_LT(ascii_allocations.bytes(), kFailFastBytes);
  expectMessageHas(caught_ascii, {kName, "element 'face'"});
}

TEST(PlyReaderErrors, TruncatedBinaryBody) {
  for (PlyFormat format : {PlyFormat::BinaryLittleEndian, PlyFormat::BinaryBigEndian}) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string header = plyHeader(
        format, {"element vertex 3", "property float x", "property float y", "property float z"});
    PlyBody body(format);
    body.put(1.0f).put(2.0f).put(3.0f).put(4.0f).put(5.0f).put(6.0f).put(7.0f).put(8.0f);
    std::string file = header + body.bytes();  // 32 of the 36 bytes of the body
    for (bool parallel : {true, false}) {
      CaughtInputError caught = readError(file, parallel);
      expectMessageHas(caught, {kName, "byte offset", "element 'vertex'"});
      expectExpectedAndFound(caught);
      ASSERT_TRUE(caught.info.byte_offset.has_value());
      EXPECT_GE(*caught.info.byte_offset, header.size());
      EXPECT_LE(*caught.info.byte_offset, file.size());
    }
  }
}

TEST(PlyReaderErrors, TruncatedElementBeforeTheVertices) {
  std::string header =
      plyHeader(PlyFormat::BinaryLittleEndian,
                {"element face 2", "property list uchar int vertex_indices", "element vertex 1",
                 "property float x", "property float y", "property float z"});
  PlyBody body(PlyFormat::BinaryLittleEndian);
  body.put<std::uint8_t>(3).put(0).put(1).put(2).put<std::uint8_t>(3).put(0).put(1);
  CaughtInputError caught = readError(header + body.bytes());
  expectMessageHas(caught, {kName, "byte offset", "element 'face'", "vertex_indices"});
}

TEST(PlyReaderErrors, BinaryFileEndsBeforeTheFacesAfterTheVertices) {
  std::string header =
      plyHeader(PlyFormat::BinaryLittleEndian,
                {"element vertex 1", "property float x", "property float y", "property float z",
                 "element face 2", "property list uchar int vertex_indices"});
  PlyBody body(PlyFormat::BinaryLittleEndian);
  body.put(1.0f).put(2.0f).put(3.0f);
  CaughtInputError caught = readError(header + body.bytes());
  expectMessageHas(caught, {kName, "element 'face'"});
  expectExpectedAndFound(caught);
}

TEST(PlyReaderErrors, BinaryListRunsPastTheEndOfTheFile) {
  for (PlyFormat format : {PlyFormat::BinaryLittleEndian, PlyFormat::BinaryBigEndian}) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string header =
        plyHeader(format, {"element vertex 2", "property float x", "property float y",
                           "property float z", "property list uchar int ids"});
    PlyBody body(format);
    body.put(1.0f).put(2.0f).put(3.0f).put<std::uint8_t>(1).put(7);
    body.put(4.0f).put(5.0f).put(6.0f).put<std::uint8_t>(200).put(8).put(9);
    std::string file = header + body.bytes();
    for (bool parallel : {true, false}) {
      CaughtInputError caught = readError(file, parallel);
      expectMessageHas(caught, {kName, "byte offset", "element 'vertex'", "property 'ids'"});
      expectExpectedAndFound(caught);
      ASSERT_TRUE(caught.info.byte_offset.has_value());
      EXPECT_GE(*caught.info.byte_offset, header.size());
      EXPECT_LE(*caught.info.byte_offset, file.size());
    }
  }
}

TEST(PlyReaderErrors, BinaryUintListCountRunsPastTheEnd) {
  std::string header = plyHeader(PlyFormat::BinaryLittleEndian,
                                 {"element vertex 1", "property float x", "property float y",
                                  "property float z", "property list uint double samples"});
  PlyBody body(PlyFormat::BinaryLittleEndian);
  body.put(1.0f).put(2.0f).put(3.0f).put<std::uint32_t>(4294967295u).put(0.5);
  test::AllocationScope allocations;
  CaughtInputError caught = readError(header + body.bytes());
  EXPECT_LT(allocations.bytes(), kFailFastBytes);
  expectMessageHas(caught, {kName, "byte offset", "property 'samples'"});
}

TEST(PlyReaderErrors, NegativeBinaryListCount) {
  std::string header = plyHeader(PlyFormat::BinaryLittleEndian,
                                 {"element vertex 2", "property float x", "property float y",
                                  "property float z", "property list char int ids"});
  PlyBody body(PlyFormat::BinaryLittleEndian);
  body.put(1.0f).put(2.0f).put(3.0f).put<std::int8_t>(0);
  body.put(4.0f).put(5.0f).put(6.0f).put<std::int8_t>(-1).put(0).put(0).put(0).put(0);
  CaughtInputError caught = readError(header + body.bytes());
  expectMessageHas(caught, {kName, "element 'vertex'", "property 'ids'", "-1"});
  expectExpectedAndFound(caught);

  std::string int_header = plyHeader(PlyFormat::BinaryBigEndian,
                                     {"element vertex 1", "property float x", "property float y",
                                      "property float z", "property list int uchar ids"});
  PlyBody int_body(PlyFormat::BinaryBigEndian);
  int_body.put(1.0f).put(2.0f).put(3.0f).put<std::int32_t>(-2).put(0);
  CaughtInputError int_caught = readError(int_header + int_body.bytes());
  expectMessageHas(int_caught, {kName, "element 'vertex'", "property 'ids'", "-2"});
}

// Assumption (PLY lists are counted by an integer): a floating-point count type is rejected in
// the header.
TEST(PlyReaderErrors, FloatingPointListCountType) {
  CaughtInputError caught = readError(plyHeader(
      PlyFormat::BinaryLittleEndian, {"element vertex 1", "property float x", "property float y",
                                      "property float z", "property list float int ids"}));
  expectMessageHas(caught, {kName, "line 7", "float"});
  expectExpectedAndFound(caught);
}

// ---------------------------------------------------------------------------------------------
// Ascii body

TEST(PlyReaderErrors, AsciiNonNumber) {
  for (bool parallel : {true, false}) {
    CaughtInputError caught = readError(asciiXyz("1 2 3\n4 abc 6\n"), parallel);
    expectMessageHas(caught, {kName, "line 9", "element 'vertex'", "property 'y'", "abc"});
    expectExpectedAndFound(caught);
    EXPECT_NE(caught.info.found.find("abc"), std::string::npos) << caught.message;
  }
}

TEST(PlyReaderErrors, AsciiNumberWithTrailingGarbage) {
  CaughtInputError caught = readError(asciiXyz("1 2 3\n4 5 6.5q\n"));
  expectMessageHas(caught, {kName, "line 9", "property 'z'", "6.5q"});
}

TEST(PlyReaderErrors, AsciiTooFewValues) {
  for (bool parallel : {true, false}) {
    // Long enough that the file could hold two records: the line itself is at fault.
    CaughtInputError caught = readError(asciiXyz("1.25 2.5\n4 5 6\n"), parallel);
    expectMessageHas(caught, {kName, "line 8", "element 'vertex'", "property 'z'"});
    expectExpectedAndFound(caught);
  }
}

TEST(PlyReaderErrors, AsciiTooManyValues) {
  for (bool parallel : {true, false}) {
    CaughtInputError caught = readError(asciiXyz("1 2 3\n4 5 6 7\n"), parallel);
    expectMessageHas(caught, {kName, "line 9", "element 'vertex'"});
    expectExpectedAndFound(caught);
  }
}

TEST(PlyReaderErrors, AsciiFewerLinesThanTheCount) {
  // Too short for two records at all: may be caught before decoding, at the body's first line.
  CaughtInputError caught = readError(asciiXyz("1 2 3\n"));
  expectMessageHas(caught, {kName, "element 'vertex'"});
  expectExpectedAndFound(caught);
  EXPECT_TRUE(caught.message.find("line 8") != std::string::npos ||
              caught.message.find("line 9") != std::string::npos)
      << caught.message;
  // Long enough for two records by size, but only one line: the missing line 9 is named.
  for (bool parallel : {true, false}) {
    CaughtInputError missing = readError(asciiXyz("1.25 2.25 3.25\n"), parallel);
    expectMessageHas(missing, {kName, "line 9", "element 'vertex'"});
    expectExpectedAndFound(missing);
  }
}

TEST(PlyReaderErrors, AsciiMoreLinesThanTheCount) {
  CaughtInputError caught = readError(asciiXyz("1 2 3\n4 5 6\n7 8 9\n"));
  expectMessageHas(caught, {kName, "line 10", "element 'vertex'"});
  expectExpectedAndFound(caught);
}

TEST(PlyReaderErrors, AsciiListRunsPastTheEndOfTheLine) {
  std::string file =
      plyHeader(PlyFormat::Ascii, {"element vertex 2", "property float x", "property float y",
                                   "property float z", "property list uchar int ids"}) +
      "1 2 3 2 10 11\n4 5 6 5 1 2\n";
  for (bool parallel : {true, false}) {
    CaughtInputError caught = readError(file, parallel);
    expectMessageHas(caught, {kName, "line 10", "element 'vertex'", "property 'ids'"});
    expectExpectedAndFound(caught);
  }
}

TEST(PlyReaderErrors, AsciiNegativeListCount) {
  std::string file =
      plyHeader(PlyFormat::Ascii, {"element vertex 1", "property float x", "property float y",
                                   "property float z", "property list int int ids"}) +
      "1 2 3 -1 5\n";
  CaughtInputError caught = readError(file);
  expectMessageHas(caught, {kName, "line 9", "property 'ids'", "-1"});
  expectExpectedAndFound(caught);
}

TEST(PlyReaderErrors, AsciiIntegerOutOfRangeForItsType) {
  struct Case {
    std::string type;
    std::string value;
  };
  const Case cases[] = {{"uchar", "300"},       {"uchar", "-1"},     {"char", "128"},
                        {"ushort", "70000"},    {"short", "-32769"}, {"int", "2147483648"},
                        {"uint", "4294967296"}, {"uint", "-5"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.type + " " + c.value);
    std::string file =
        plyHeader(PlyFormat::Ascii, {"element vertex 1", "property float x", "property float y",
                                     "property float z", "property " + c.type + " label"}) +
        "1 2 3 " + c.value + "\n";
    CaughtInputError caught = readError(file);
    expectMessageHas(caught, {kName, "line 9", "property 'label'", c.value});
    expectExpectedAndFound(caught);
  }
}

TEST(PlyReaderErrors, AsciiFractionForAnIntegerProperty) {
  std::string file =
      plyHeader(PlyFormat::Ascii, {"element vertex 1", "property float x", "property float y",
                                   "property float z", "property uchar red"}) +
      "1 2 3 2.5\n";
  CaughtInputError caught = readError(file);
  expectMessageHas(caught, {kName, "line 9", "property 'red'", "2.5"});
}

TEST(PlyReaderErrors, AsciiErrorInAnElementBeforeTheVertices) {
  std::string file =
      plyHeader(PlyFormat::Ascii,
                {"element face 2", "property list uchar int vertex_indices", "element vertex 1",
                 "property float x", "property float y", "property float z"}) +
      "3 0 1 2\n3 0 x 2\n1 2 3\n";
  CaughtInputError caught = readError(file);
  expectMessageHas(caught, {kName, "line 11", "element 'face'", "property 'vertex_indices'"});
}

// ---------------------------------------------------------------------------------------------
// PlyChunkReader

TEST(PlyReaderErrors, ChunkReaderPointOutsideTheGivenQuantization) {
  test::TempDir dir;
  std::string file = plyHeader(PlyFormat::BinaryLittleEndian, kXyz);
  PlyBody body(PlyFormat::BinaryLittleEndian);
  body.put(1.0f).put(2.0f).put(3.0f).put(1.0e6f).put(2.0f).put(3.0f);
  auto path = dir.write("outside.ply", file + body.bytes());
  PlyChunkReader reader(path);
  Quantization tight;
  tight.scale = {1e-6, 1e-6, 1e-6};
  reader.setQuantization(tight);
  PointCloud chunk;
  CaughtInputError caught = catchInputError([&] {
    while (reader.next(chunk, 1)) {
    }
  });
  expectMessageHas(caught, {"outside.ply", "element 'vertex'"});
  EXPECT_FALSE(caught.info.hint.empty()) << caught.message;
}

TEST(PlyReaderErrors, ChunkReaderTruncatedBody) {
  test::TempDir dir;
  std::string file = plyHeader(PlyFormat::BinaryBigEndian, kXyz);
  PlyBody body(PlyFormat::BinaryBigEndian);
  body.put(1.0f).put(2.0f).put(3.0f).put(4.0f);
  auto path = dir.write("short.ply", file + body.bytes());
  CaughtInputError caught = catchInputError([&] {
    PlyChunkReader reader(path);
    PointCloud chunk;
    while (reader.next(chunk, 1)) {
    }
  });
  expectMessageHas(caught, {"short.ply", "element 'vertex'"});
}

// ---------------------------------------------------------------------------------------------
// Damaged copies of a valid file: never a crash, never another exception type.

// A small file with a bit of everything: positions, colours, an extra, a list, a face element.
struct SmallFile {
  std::string bytes;
  std::size_t vertex_end = 0;  // first byte after the vertex element
};

SmallFile smallValidFile(PlyFormat format) {
  std::string header = plyHeader(
      format, {"comment damaged copies", "element vertex 3", "property float x", "property float y",
               "property double z", "property uchar red", "property uchar green",
               "property uchar blue", "property list uchar int ids", "property ushort quality",
               "element face 1", "property list uchar uint vertex_indices"});
  PlyBody body(format);
  body.put(1.5f).put(-2.0f).put(596732.4375).put<std::uint8_t>(1).put<std::uint8_t>(2);
  body.put<std::uint8_t>(3).put<std::uint8_t>(2).put(7).put(8).put<std::uint16_t>(65535).end();
  body.put(4.0f).put(5.0f).put(596733.0).put<std::uint8_t>(4).put<std::uint8_t>(5);
  body.put<std::uint8_t>(6).put<std::uint8_t>(0).put<std::uint16_t>(0).end();
  body.put(0.25f).put(0.5f).put(596734.5).put<std::uint8_t>(7).put<std::uint8_t>(8);
  body.put<std::uint8_t>(9).put<std::uint8_t>(1).put(-1).put<std::uint16_t>(12).end();
  std::size_t vertex_end = header.size() + body.bytes().size();
  body.put<std::uint8_t>(3).put<std::uint32_t>(0).put<std::uint32_t>(1).put<std::uint32_t>(2);
  body.end();
  return {header + body.bytes(), vertex_end};
}

// Reads `bytes`; true when it read, false on InputError; any other outcome is a failure.
bool readsOrInputError(const std::string& bytes, bool parallel) {
  PlyReadOptions options;
  options.parallel = parallel;
  try {
    PointCloud cloud = readPlyFromMemory(asBytes(bytes), kName, options);
    EXPECT_EQ(cloud.positions.size(), cloud.count);
    return true;
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(kName), std::string::npos) << error.what();
    return false;
  } catch (const std::exception& error) {
    ADD_FAILURE() << "not an InputError: " << error.what();
    return false;
  }
}

TEST(PlyReaderErrors, EveryTruncationBeforeTheEndOfTheVerticesIsAnInputError) {
  for (PlyFormat format : test::kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    SmallFile file = smallValidFile(format);
    ASSERT_TRUE(readsOrInputError(file.bytes, true));
    // In ascii the last value, "12\n", still reads when cut to "1" or "12".
    std::size_t strict_end = format == PlyFormat::Ascii ? file.vertex_end - 2 : file.vertex_end;
    std::string accepted;
    for (std::size_t size = 0; size < strict_end; ++size) {
      if (readsOrInputError(file.bytes.substr(0, size), size % 2 == 0)) {
        (accepted += ' ') += std::to_string(size);
      }
    }
    EXPECT_EQ(accepted, "") << "copies cut to these sizes of " << file.bytes.size()
                            << " bytes were accepted";
  }
}

// The header promises a face after the vertices; a file cut inside it (or before it) is
// truncated even though every point is there.
TEST(PlyReaderErrors, TruncationInsideATrailingElementIsAnInputError) {
  for (PlyFormat format : test::kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    SmallFile file = smallValidFile(format);
    // An ascii file may lack its last line end.
    std::size_t end = file.bytes.size() - (format == PlyFormat::Ascii ? 1 : 0);
    std::string accepted;
    for (std::size_t size = file.vertex_end; size < end; ++size) {
      if (readsOrInputError(file.bytes.substr(0, size), size % 2 == 0)) {
        (accepted += ' ') += std::to_string(size);
      }
    }
    EXPECT_EQ(accepted, "") << "copies cut to these sizes of " << file.bytes.size()
                            << " bytes (the vertices end at " << file.vertex_end
                            << ") were accepted";
  }
}

TEST(PlyReaderErrors, EveryDamagedByteReadsOrIsAnInputError) {
  const char replacements[] = {'\0', '\xff', '\n', ' ', '-', '9', '\x80'};
  for (PlyFormat format : test::kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string file = smallValidFile(format).bytes;
    for (std::size_t at = 0; at < file.size(); ++at) {
      for (char replacement : replacements) {
        std::string damaged = file;
        damaged[at] = replacement;
        readsOrInputError(damaged, at % 2 == 0);
      }
    }
  }
}

TEST(PlyReaderErrors, EveryDamagedByteStreamsOrIsAnInputError) {
  test::TempDir dir;
  // Every third byte, with a rotating replacement: each case writes a file, which is slow.
  const char replacements[] = {'\0', '\xff', '\n'};
  for (PlyFormat format : test::kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    std::string file = smallValidFile(format).bytes;
    for (std::size_t at = 0; at < file.size(); at += 3) {
      std::string damaged = file;
      damaged[at] = replacements[(at / 3) % 3];
      auto path = dir.write("damaged.ply", damaged);
      try {
        PlyChunkReader reader(path);
        PointCloud chunk;
        std::uint64_t total = 0;
        while (reader.next(chunk, 2)) total += chunk.count;
        EXPECT_EQ(total, reader.pointCount());
      } catch (const InputError& error) {
        EXPECT_NE(std::string(error.what()).find("damaged.ply"), std::string::npos) << error.what();
      } catch (const std::exception& error) {
        ADD_FAILURE() << "byte " << at << ": not an InputError: " << error.what();
      }
    }
  }
}

}  // namespace
}  // namespace parallax
