// PLY headers as real exporters write them: blanks after the words of a line (the first line
// "ply " included), CR before LF, blank lines. Format detection by content and the header parser
// take them; the body starts right after the LF that ends "end_header" (a binary body whose first
// bytes are blanks, CR or LF is not eaten); a header that is really broken is still reported
// with its line and what was expected.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/ply_header.h"
#include "io/ply_reader.h"
#include "io/ply_test_files.h"
#include "io/point_file.h"
#include "support/temp_dir.h"

namespace parallax {
namespace {

using test::asBytes;
using test::catchInputError;
using test::CaughtInputError;
using test::expectMessageHas;
using test::PlyBody;

// One way of decorating header lines: what follows "ply", what follows every other line's words.
struct HeaderStyle {
  const char* name;
  std::string after_ply;    // between "ply" and the line end
  std::string after_words;  // between the other lines' last word and the line end
  std::string eol;          // the line end
};

const std::vector<HeaderStyle> kStyles = {
    {"space after ply", " ", "", "\n"},
    {"tab after ply", "\t", "", "\n"},
    {"crlf", "", "", "\r\n"},
    {"space after ply, crlf", " ", "", "\r\n"},
    {"blanks after every line", "  ", " \t", "\n"},
    {"blanks after every line, crlf", " \t", "\t ", "\r\n"},
    {"cr cr lf", "", "\r", "\r\n"},
};

// The header in `style`; a blank line after the comment, as some writers leave.
std::string styledHeader(const HeaderStyle& style, PlyFormat format) {
  std::string text = "ply" + style.after_ply + style.eol;
  for (const std::string& line :
       {"format " + test::formatKeyword(format) + " 1.0", std::string("comment made by hand"),
        std::string(""), std::string("element vertex 3"), std::string("property uchar tag"),
        std::string("property float x"), std::string("property float y"),
        std::string("property float z"), std::string("end_header")}) {
    text += line + (line.empty() ? "" : style.after_words) + style.eol;
  }
  return text;
}

// Tags 10, 13 and 32 are LF, CR and a space: a binary body starting with them must not be read
// as the rest of the header's last line end.
struct Point {
  std::uint8_t tag;
  float x, y, z;
};
const Point kPoints[] = {
    {10, 1.5f, -2.25f, 3.0f}, {13, 0.125f, 4.0f, -5.5f}, {32, 6.0f, 7.75f, 8.5f}};

std::string body(const HeaderStyle& style, PlyFormat format) {
  PlyBody b(format);
  for (const Point& p : kPoints) b.put(p.tag).put(p.x).put(p.y).put(p.z).end(style.eol);
  return b.bytes();
}

TEST(PlyExporterHeaders, EveryStyleAndFormatIsDetectedParsedAndReadExactly) {
  for (const HeaderStyle& style : kStyles) {
    for (PlyFormat format : test::kAllPlyFormats) {
      SCOPED_TRACE(std::string(style.name) + ", " + test::formatKeyword(format));
      const std::string header_text = styledHeader(style, format);
      const std::string file = header_text + body(style, format);

      EXPECT_EQ(detectPointFormatFromMemory(asBytes(file)), PointFormat::Ply);
      const PlyHeader header = parsePlyHeader(asBytes(file), "styled.ply");
      EXPECT_EQ(header.format, format);
      EXPECT_EQ(header.body_offset, header_text.size());
      EXPECT_EQ(header.body_line, 11u);
      EXPECT_EQ(header.comments, std::vector<std::string>{"made by hand"});
      ASSERT_EQ(header.elements.size(), 1u);
      EXPECT_EQ(header.elements[0].count, 3u);
      ASSERT_EQ(header.elements[0].properties.size(), 4u);
      EXPECT_EQ(header.elements[0].properties[3].name, "z");

      const PointCloud cloud = test::readPlyText(file);
      ASSERT_EQ(cloud.count, 3u);
      const std::vector<std::uint8_t> tags =
          test::scalarValues<std::uint8_t>(cloud, "tag", ScalarType::UInt8);
      ASSERT_EQ(tags.size(), 3u);
      for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(tags[i], kPoints[i].tag) << "point " << i;
        EXPECT_EQ(cloud.worldX(i), kPoints[i].x) << "point " << i;
        EXPECT_EQ(cloud.worldY(i), kPoints[i].y) << "point " << i;
        EXPECT_EQ(cloud.worldZ(i), kPoints[i].z) << "point " << i;
      }
    }
  }
}

TEST(PlyExporterHeaders, FilesOnDiskAreDetectedAndReadByContent) {
  test::TempDir dir;
  const HeaderStyle& style = kStyles[5];  // blanks after every line, crlf
  for (PlyFormat format : test::kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    // A misleading extension: detection goes by content.
    const auto path = dir.write("scan_" + test::formatKeyword(format) + ".txt",
                                styledHeader(style, format) + body(style, format));
    EXPECT_EQ(detectPointFormat(path), PointFormat::Ply);
    const PointCloud cloud = readPointFile(path);
    ASSERT_EQ(cloud.count, 3u);
    EXPECT_EQ(cloud.worldZ(2), 8.5);
  }
}

TEST(PlyExporterHeaders, ChunkReaderStartsTheBinaryBodyAfterTheRealLineEnd) {
  test::TempDir dir;
  const HeaderStyle& style = kStyles[6];  // cr cr lf
  const auto path = dir.write("chunked.ply", styledHeader(style, PlyFormat::BinaryLittleEndian) +
                                                 body(style, PlyFormat::BinaryLittleEndian));
  PlyChunkReader reader(path);
  PointCloud chunk;
  std::vector<float> xs;
  while (reader.next(chunk, 2)) {
    for (std::size_t i = 0; i < chunk.count; ++i) xs.push_back(float(chunk.worldX(i)));
  }
  EXPECT_EQ(xs, (std::vector<float>{1.5f, 0.125f, 6.0f}));
}

CaughtInputError exporterHeaderError(const std::string& text) {
  return catchInputError([&] { parsePlyHeader(asBytes(text), "broken.ply"); });
}

TEST(PlyExporterHeaders, OtherWordsOnThePlyLineAreReportedOnLineOne) {
  const std::string text = "ply binary\nformat ascii 1.0\nelement vertex 0\nend_header\n";
  // Detected as PLY, so that the parser (not "unknown format") says what is wrong.
  EXPECT_EQ(detectPointFormatFromMemory(asBytes(text)), PointFormat::Ply);
  const CaughtInputError caught = exporterHeaderError(text);
  expectMessageHas(caught, {"broken.ply", "line 1", "ply binary"});
  EXPECT_EQ(caught.info.line, 1u);
  EXPECT_NE(caught.info.expected.find("'ply'"), std::string::npos) << caught.message;
}

TEST(PlyExporterHeaders, OtherWordsAfterEndHeaderAreReportedWithTheirLine) {
  const CaughtInputError caught =
      exporterHeaderError("ply\nformat ascii 1.0\nelement vertex 0\nend_header vertex\n");
  expectMessageHas(caught, {"line 4", "end_header vertex"});
  EXPECT_EQ(caught.info.line, 4u);
  EXPECT_NE(caught.info.expected.find("'end_header' alone"), std::string::npos) << caught.message;
}

TEST(PlyExporterHeaders, BlanksInsideAWordAreStillAnError) {
  const CaughtInputError caught =
      exporterHeaderError("ply \r\nformat ascii 1.0 \r\nelement vertex 1 2\r\nend_header\r\n");
  expectMessageHas(caught, {"line 3", "element vertex 1 2"});
  EXPECT_EQ(caught.info.line, 3u);
  EXPECT_EQ(caught.info.expected, "'element <name> <count>'");
}

TEST(PlyExporterHeaders, LinesEndingInCrAloneAreNamedAsSuch) {
  const std::string text = "ply\rformat ascii 1.0\relement vertex 0\rend_header\r";
  EXPECT_EQ(detectPointFormatFromMemory(asBytes(text)), PointFormat::Ply);
  const CaughtInputError caught = exporterHeaderError(text);
  expectMessageHas(caught, {"broken.ply", "line 1", "CR alone"});
}

TEST(PlyExporterHeaders, PlyInsideAWordIsNotAPlyFile) {
  // "plywood" is a word of a text file, not the PLY signature.
  const std::string text = "plywood 1 2 3\n1 2 3\n";
  EXPECT_NE(detectPointFormatFromMemory(asBytes(text)), PointFormat::Ply);
}

}  // namespace
}  // namespace parallax
