// Bad E57 input: each refused with an InputError naming the file, the byte offset (a page's, the
// header's, the XML section's) or the XML element, and what was expected.
#include <gtest/gtest.h>

#include "core/error.h"
#include "io/e57/e57_document.h"
#include "io/e57/e57_reader.h"
#include "io/e57/e57_test_files.h"

namespace parallax {
namespace {

// The message of reading `bytes`, or "" when it reads.
std::string errorOf(const std::string& bytes) {
  try {
    readE57FromMemory({reinterpret_cast<const std::byte*>(bytes.data()), bytes.size()}, "bad.e57");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

std::string pdal(const char* name) {
  return test::readBytes(test::e57DataFile(name));
}

TEST(E57Errors, ABadChecksumNamesItsPage) {
  std::string file = pdal("A_B.e57");
  ASSERT_EQ(file.size(), 6144u);
  file[2 * 1024 + 100] ^= 0x01;  // a byte of page 2 (the XML section lies there)
  const std::string message = errorOf(file);
  EXPECT_NE(message.find("bad.e57: byte offset 2048, element 'page 2', property 'CRC-32C"),
            std::string::npos)
      << message;
  // The same byte changed and the page resealed: the checksum is not what refuses it then.
  test::resealPages(file);
  EXPECT_EQ(errorOf(file).find("CRC-32C"), std::string::npos);
}

TEST(E57Errors, ATruncatedFileSaysSo) {
  const std::string file = pdal("A4.e57");
  std::string message = errorOf(file.substr(0, 3000));
  EXPECT_NE(message.find("byte offset 16, element 'E57 file header', property "
                         "'filePhysicalLength': expected 4096 bytes (the header's), found a "
                         "file of 3000 bytes. the file is truncated"),
            std::string::npos)
      << message;
  // A truncated page whose header was mended to the shorter length: the XML section's range
  // is past the end.
  std::string cut = file.substr(0, 2048 + 500);
  cut[16] = char(0xF4), cut[17] = char(0x09);  // 2548, little endian
  message = errorOf(cut);
  EXPECT_NE(message.find("whole number of 1024-byte pages"), std::string::npos) << message;
  EXPECT_NE(errorOf(file.substr(0, 20)).find("signature"), std::string::npos);
  EXPECT_NE(errorOf("ASTM-E58" + file.substr(8)).find("expected \"ASTM-E57\""), std::string::npos);
}

TEST(E57Errors, XmlThatIsNotWellFormedNamesItsLine) {
  std::string file = pdal("A4.e57");
  ASSERT_TRUE(test::replaceSealed(file, "</data3D>", "</data3X>"));
  const std::string message = errorOf(file);
  EXPECT_NE(message.find("element 'XML section': expected well-formed XML"), std::string::npos)
      << message;
  EXPECT_NE(message.find("line "), std::string::npos) << message;
  EXPECT_NE(message.find("data3D"), std::string::npos) << message;  // libxml2 names the tag
}

TEST(E57Errors, AMissingFieldIsNamedWithItsPath) {
  std::string file = pdal("A4.e57");
  ASSERT_TRUE(test::replaceSealed(file, "<cartesianX ", "<cartesianQ "));
  ASSERT_TRUE(test::replaceSealed(file, "</cartesianX>", "</cartesianQ>"));
  const std::string message = errorOf(file);
  EXPECT_NE(message.find("element 'XML /data3D/0/points/prototype', property 'cartesianX': "
                         "expected a field of the point record"),
            std::string::npos)
      << message;
  std::string no_points = pdal("A4.e57");
  ASSERT_TRUE(test::replaceSealed(no_points, "<points ", "<pointz "));
  ASSERT_TRUE(test::replaceSealed(no_points, "</points>", "</pointz>"));
  EXPECT_NE(errorOf(no_points).find("element 'XML /data3D/0', property 'points'"),
            std::string::npos);
  std::string bad_count = pdal("A4.e57");
  ASSERT_TRUE(test::replaceSealed(bad_count, "recordCount=\"4\"", "recordCount=\"x\""));
  EXPECT_NE(errorOf(bad_count).find("property 'recordCount': expected an integer, found 'x'"),
            std::string::npos);
}

TEST(E57Errors, MoreRecordsThanTheBytestreamsHold) {
  std::string file = pdal("A4.e57");
  ASSERT_TRUE(test::replaceSealed(file, "recordCount=\"4\"", "recordCount=\"9\""));
  const std::string message = errorOf(file);
  EXPECT_NE(message.find("element 'scan 0', property 'cartesianX': expected 9 records "
                         "(recordCount), found the bytestream ends after 4"),
            std::string::npos)
      << message;
}

TEST(E57Errors, ABadPacketOrSectionNamesItsOffset) {
  std::string file = pdal("A4.e57");
  // A4's compressed vector section is at physical offset 48 (its XML says fileOffset="48"):
  // its id byte, then its first data packet's bytestream count (at 48 + 32 + 4).
  std::string bad_section = file;
  bad_section[48] = 7;
  test::resealPages(bad_section);
  EXPECT_NE(errorOf(bad_section)
                .find("byte offset 48, element 'compressed vector section of "
                      "scan 0', property 'section id': expected 1"),
            std::string::npos);
  std::string bad_packet = file;
  bad_packet[48 + 32 + 4] = 3;
  test::resealPages(bad_packet);
  const std::string message = errorOf(bad_packet);
  EXPECT_NE(message.find("byte offset 80, element 'packet of scan 0', property "
                         "'bytestreamCount': expected 7 (the fields of the prototype), found 3"),
            std::string::npos)
      << message;
}

TEST(E57Document, ImagesAreListedNotDecoded) {
  const std::string xml = R"(<?xml version="1.0"?>
<e57Root type="Structure" xmlns="http://www.astm.org/COMMIT/E57/2010-e57-v1.0">
 <data3D type="Vector"/>
 <images2D type="Vector">
  <vectorChild type="Structure">
   <name type="String">camera 1</name>
   <pinholeRepresentation type="Structure">
    <jpegImage type="Blob" fileOffset="4096" length="123456"/>
    <imageWidth type="Integer">4000</imageWidth>
    <imageHeight type="Integer">3000</imageHeight>
   </pinholeRepresentation>
  </vectorChild>
  <vectorChild type="Structure">
   <sphericalRepresentation type="Structure">
    <pngImage type="Blob" fileOffset="9000" length="77"/>
   </sphericalRepresentation>
  </vectorChild>
 </images2D>
</e57Root>)";
  const E57Document document = parseE57Document(xml, "images.e57", 1024);
  EXPECT_TRUE(document.scans.empty());
  ASSERT_EQ(document.images.size(), 2u);
  EXPECT_EQ(document.images[0].name, "camera 1");
  EXPECT_EQ(document.images[0].representation, "pinhole");
  EXPECT_EQ(document.images[0].format, "JPEG");
  EXPECT_EQ(document.images[0].width, 4000);
  EXPECT_EQ(document.images[0].height, 3000);
  EXPECT_EQ(document.images[0].byte_length, 123456u);
  EXPECT_EQ(document.images[1].representation, "spherical");
  EXPECT_EQ(document.images[1].format, "PNG");
  EXPECT_EQ(document.images[1].byte_length, 77u);
}

}  // namespace
}  // namespace parallax
