// parsePlyHeader and formatPlyHeader: the header as written, and the sizes derived from it.
#include "io/ply_header.h"

#include <gtest/gtest.h>

#include <string>

#include "io/ply_test_files.h"

namespace parallax {
namespace {

using test::asBytes;

PlyHeader parse(const std::string& text) {
  return parsePlyHeader(asBytes(text), "test.ply");
}

TEST(PlyHeader, ParsesFormatVersionElementsAndProperties) {
  std::string text =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "element vertex 7\n"
      "property float x\n"
      "property double y\n"
      "property uchar red\n"
      "element face 3\n"
      "property list uchar int vertex_indices\n"
      "end_header\n";
  PlyHeader header = parse(text);
  EXPECT_EQ(header.format, PlyFormat::BinaryLittleEndian);
  EXPECT_EQ(header.version, "1.0");
  ASSERT_EQ(header.elements.size(), 2u);

  const PlyElement& vertex = header.elements[0];
  EXPECT_EQ(vertex.name, "vertex");
  EXPECT_EQ(vertex.count, 7u);
  EXPECT_EQ(vertex.header_line, 3u);
  ASSERT_EQ(vertex.properties.size(), 3u);
  EXPECT_EQ(vertex.properties[0].name, "x");
  EXPECT_EQ(vertex.properties[0].type, ScalarType::Float32);
  EXPECT_FALSE(vertex.properties[0].is_list);
  EXPECT_EQ(vertex.properties[0].header_line, 4u);
  EXPECT_EQ(vertex.properties[1].name, "y");
  EXPECT_EQ(vertex.properties[1].type, ScalarType::Float64);
  EXPECT_EQ(vertex.properties[2].name, "red");
  EXPECT_EQ(vertex.properties[2].type, ScalarType::UInt8);
  EXPECT_EQ(vertex.properties[2].header_line, 6u);

  const PlyElement& face = header.elements[1];
  EXPECT_EQ(face.name, "face");
  EXPECT_EQ(face.count, 3u);
  EXPECT_EQ(face.header_line, 7u);
  ASSERT_EQ(face.properties.size(), 1u);
  EXPECT_EQ(face.properties[0].name, "vertex_indices");
  EXPECT_TRUE(face.properties[0].is_list);
  EXPECT_EQ(face.properties[0].list_count_type, ScalarType::UInt8);
  EXPECT_EQ(face.properties[0].type, ScalarType::Int32);

  EXPECT_EQ(header.body_offset, text.size());
  EXPECT_EQ(header.body_line, 10u);
}

TEST(PlyHeader, ParsesEveryFormatKeyword) {
  for (PlyFormat format : test::kAllPlyFormats) {
    SCOPED_TRACE(test::formatKeyword(format));
    PlyHeader header = parse(test::plyHeader(format, {"element vertex 0", "property float x"}));
    EXPECT_EQ(header.format, format);
    EXPECT_EQ(plyFormatName(format), test::formatKeyword(format));
  }
}

TEST(PlyHeader, AcceptsCanonicalTypeNamesAndSizedAliases) {
  std::string text = test::plyHeader(
      PlyFormat::Ascii,
      {"element vertex 1", "property char a", "property uchar b", "property short c",
       "property ushort d", "property int e", "property uint f", "property float g",
       "property double h", "property int8 i", "property uint8 j", "property int16 k",
       "property uint16 l", "property int32 m", "property uint32 n", "property float32 o",
       "property float64 p"});
  PlyHeader header = parse(text);
  ASSERT_EQ(header.elements.size(), 1u);
  const auto& properties = header.elements[0].properties;
  ASSERT_EQ(properties.size(), 16u);
  const ScalarType expected[] = {ScalarType::Int8,    ScalarType::UInt8,  ScalarType::Int16,
                                 ScalarType::UInt16,  ScalarType::Int32,  ScalarType::UInt32,
                                 ScalarType::Float32, ScalarType::Float64};
  for (std::size_t i = 0; i < 16; ++i) {
    EXPECT_EQ(properties[i].type, expected[i % 8]) << properties[i].name;
    EXPECT_EQ(properties[i].name, std::string(1, char('a' + i)));
  }
}

TEST(PlyHeader, ListPropertiesKeepCountAndItemTypes) {
  PlyHeader header =
      parse(test::plyHeader(PlyFormat::BinaryBigEndian, {"element vertex 2", "property float x",
                                                         "property list uint16 float32 weights",
                                                         "property list uint int tags"}));
  const auto& properties = header.elements[0].properties;
  ASSERT_EQ(properties.size(), 3u);
  EXPECT_TRUE(properties[1].is_list);
  EXPECT_EQ(properties[1].name, "weights");
  EXPECT_EQ(properties[1].list_count_type, ScalarType::UInt16);
  EXPECT_EQ(properties[1].type, ScalarType::Float32);
  EXPECT_TRUE(properties[2].is_list);
  EXPECT_EQ(properties[2].list_count_type, ScalarType::UInt32);
  EXPECT_EQ(properties[2].type, ScalarType::Int32);
}

TEST(PlyHeader, KeepsCommentsAndObjInfo) {
  PlyHeader header = parse(test::plyHeader(
      PlyFormat::Ascii, {"comment made by hand", "obj_info scanner 7", "element vertex 1",
                         "comment between properties", "property float x"}));
  EXPECT_EQ(header.comments, (std::vector<std::string>{"made by hand", "between properties"}));
  EXPECT_EQ(header.obj_info, (std::vector<std::string>{"scanner 7"}));
  ASSERT_EQ(header.elements.size(), 1u);
  EXPECT_EQ(header.elements[0].properties.size(), 1u);
  EXPECT_EQ(header.elements[0].properties[0].header_line, 7u);
}

TEST(PlyHeader, AcceptsCrlfLineEnds) {
  std::string text = test::plyHeader(
      PlyFormat::Ascii, {"comment crlf", "element vertex 2", "property float x"}, "\r\n");
  PlyHeader header = parse(text + "1\r\n2\r\n");
  EXPECT_EQ(header.format, PlyFormat::Ascii);
  EXPECT_EQ(header.version, "1.0");
  EXPECT_EQ(header.comments, (std::vector<std::string>{"crlf"}));
  ASSERT_EQ(header.elements.size(), 1u);
  EXPECT_EQ(header.elements[0].name, "vertex");
  EXPECT_EQ(header.elements[0].count, 2u);
  ASSERT_EQ(header.elements[0].properties.size(), 1u);
  EXPECT_EQ(header.elements[0].properties[0].name, "x");
  EXPECT_EQ(header.body_offset, text.size());
  EXPECT_EQ(header.body_line, 7u);
}

TEST(PlyHeader, AcceptsExtraSpacesAndTabs) {
  std::string text =
      "ply\n"
      "format \t binary_big_endian   1.0  \n"
      "element\tvertex\t\t5 \n"
      "  property   float\tx\t\n"
      "property list  uchar\tint  idx\n"
      "end_header\n";
  PlyHeader header = parse(text);
  EXPECT_EQ(header.format, PlyFormat::BinaryBigEndian);
  EXPECT_EQ(header.version, "1.0");
  ASSERT_EQ(header.elements.size(), 1u);
  EXPECT_EQ(header.elements[0].name, "vertex");
  EXPECT_EQ(header.elements[0].count, 5u);
  ASSERT_EQ(header.elements[0].properties.size(), 2u);
  EXPECT_EQ(header.elements[0].properties[0].name, "x");
  EXPECT_EQ(header.elements[0].properties[0].type, ScalarType::Float32);
  EXPECT_EQ(header.elements[0].properties[1].name, "idx");
  EXPECT_TRUE(header.elements[0].properties[1].is_list);
  EXPECT_EQ(header.body_offset, text.size());
}

TEST(PlyHeader, BodyOffsetPointsAtTheFirstBodyByte) {
  std::string header_text =
      test::plyHeader(PlyFormat::BinaryLittleEndian, {"element vertex 1", "property uchar v"});
  // The body's first byte is '\n' (value 10): it must not be taken as part of the header.
  std::string text = header_text + "\n";
  PlyHeader header = parse(text);
  EXPECT_EQ(header.body_offset, header_text.size());
}

TEST(PlyHeader, BodyStartingWithCarriageReturnIsNotTakenForALineEnd) {
  std::string header_text =
      test::plyHeader(PlyFormat::BinaryBigEndian, {"element vertex 1", "property uchar v"});
  PlyHeader header = parse(header_text + "\r");
  EXPECT_EQ(header.body_offset, header_text.size());
}

TEST(PlyHeader, CommentMentioningEndHeaderDoesNotEndTheHeader) {
  std::string text = test::plyHeader(
      PlyFormat::Ascii, {"comment end_header comes later", "element vertex 1", "property float x"});
  PlyHeader header = parse(text);
  EXPECT_EQ(header.body_offset, text.size());
  ASSERT_EQ(header.elements.size(), 1u);
  EXPECT_EQ(header.elements[0].properties.size(), 1u);
}

TEST(PlyHeader, EmptyElementIsKept) {
  PlyHeader header = parse(
      test::plyHeader(PlyFormat::Ascii, {"element vertex 0", "property float x", "element face 0",
                                         "property list uchar int vertex_indices"}));
  ASSERT_EQ(header.elements.size(), 2u);
  EXPECT_EQ(header.elements[0].count, 0u);
  EXPECT_EQ(header.elements[1].count, 0u);
}

TEST(PlyHeader, LargeCountIsReadExactly) {
  PlyHeader header =
      parse(test::plyHeader(PlyFormat::Ascii, {"element vertex 4294967296", "property float x"}));
  EXPECT_EQ(header.elements[0].count, 4294967296u);
}

TEST(PlyHeader, RecordSizesAndPropertyLookup) {
  PlyHeader header = parse(test::plyHeader(
      PlyFormat::BinaryLittleEndian,
      {"element vertex 1", "property double x", "property float y", "property short z",
       "property uchar red", "element face 1", "property uchar flags",
       "property list ushort int vertex_indices", "property int material"}));
  const PlyElement& vertex = header.elements[0];
  const PlyElement& face = header.elements[1];
  EXPECT_FALSE(vertex.hasLists());
  EXPECT_EQ(vertex.fixedRecordSize(), 8u + 4u + 2u + 1u);
  EXPECT_EQ(vertex.minimumRecordSize(), 15u);
  EXPECT_TRUE(face.hasLists());
  EXPECT_EQ(face.minimumRecordSize(), 1u + 2u + 4u);
  EXPECT_EQ(vertex.findProperty("x"), 0);
  EXPECT_EQ(vertex.findProperty("z"), 2);
  EXPECT_EQ(vertex.findProperty("red"), 3);
  EXPECT_EQ(vertex.findProperty("green"), -1);
  EXPECT_EQ(face.findProperty("vertex_indices"), 1);
}

TEST(PlyHeader, PointElementIsVertexOrItsAliases) {
  for (std::string name : {"vertex", "vertices", "point", "points"}) {
    SCOPED_TRACE(name);
    std::string element = "element " + name + " 1";
    PlyHeader header =
        parse(test::plyHeader(PlyFormat::Ascii, {"element camera 1", "property float view_px",
                                                 element, "property float x"}));
    EXPECT_EQ(header.pointElement(), 1);
  }
  PlyHeader no_points = parse(test::plyHeader(
      PlyFormat::Ascii, {"element face 1", "property list uchar int vertex_indices"}));
  EXPECT_EQ(no_points.pointElement(), -1);
}

TEST(PlyHeader, FormattedHeaderParsesBackTheSame) {
  PlyHeader header;
  header.format = PlyFormat::BinaryBigEndian;
  header.comments = {"written by a test"};
  header.obj_info = {"units metres"};
  PlyElement vertex;
  vertex.name = "vertex";
  vertex.count = 12;
  vertex.properties.push_back({"x", ScalarType::Float64});
  vertex.properties.push_back({"red", ScalarType::UInt8});
  vertex.properties.push_back({"quality", ScalarType::UInt16});
  PlyElement face;
  face.name = "face";
  face.count = 2;
  PlyProperty indices{"vertex_indices", ScalarType::Int32};
  indices.is_list = true;
  indices.list_count_type = ScalarType::UInt8;
  face.properties.push_back(indices);
  header.elements = {vertex, face};

  std::string text = formatPlyHeader(header);
  ASSERT_GE(text.size(), 11u);
  EXPECT_EQ(text.substr(0, 4), "ply\n");
  EXPECT_EQ(text.substr(text.size() - 11), "end_header\n");
  EXPECT_EQ(text.find('\r'), std::string::npos);

  PlyHeader back = parse(text);
  EXPECT_EQ(back.format, PlyFormat::BinaryBigEndian);
  EXPECT_EQ(back.version, "1.0");
  EXPECT_EQ(back.comments, header.comments);
  EXPECT_EQ(back.obj_info, header.obj_info);
  EXPECT_EQ(back.body_offset, text.size());
  ASSERT_EQ(back.elements.size(), 2u);
  EXPECT_EQ(back.elements[0].name, "vertex");
  EXPECT_EQ(back.elements[0].count, 12u);
  ASSERT_EQ(back.elements[0].properties.size(), 3u);
  EXPECT_EQ(back.elements[0].properties[0].name, "x");
  EXPECT_EQ(back.elements[0].properties[0].type, ScalarType::Float64);
  EXPECT_EQ(back.elements[0].properties[2].name, "quality");
  EXPECT_EQ(back.elements[0].properties[2].type, ScalarType::UInt16);
  EXPECT_EQ(back.elements[1].name, "face");
  EXPECT_EQ(back.elements[1].count, 2u);
  ASSERT_EQ(back.elements[1].properties.size(), 1u);
  EXPECT_TRUE(back.elements[1].properties[0].is_list);
  EXPECT_EQ(back.elements[1].properties[0].list_count_type, ScalarType::UInt8);
  EXPECT_EQ(back.elements[1].properties[0].type, ScalarType::Int32);
}

}  // namespace
}  // namespace parallax
