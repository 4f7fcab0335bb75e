#include "core/error.h"

#include <gtest/gtest.h>

namespace parallax {
namespace {

TEST(InputError, MessageNamesEveryPartGiven) {
  InputError error({.file = "scan.ply",
                    .line = 12,
                    .element = "vertex",
                    .property = "x",
                    .expected = "a number",
                    .found = "'abc'",
                    .hint = "check the exporter"});
  EXPECT_STREQ(error.what(),
               "scan.ply: line 12, element 'vertex', property 'x': expected a number, found "
               "'abc'. check the exporter");
}

TEST(InputError, ByteOffsetAndFoundWithoutExpected) {
  InputError error({.file = "a.ply", .byte_offset = 4096, .found = "end of file"});
  EXPECT_STREQ(error.what(), "a.ply: byte offset 4096: end of file");
}

// A damaged PLY header's names reach the message: control characters and stray bytes must not
// reach the terminal (the fuzzer's inputs gave element names of 0x04 and 0xff runs, an escape
// sequence would recolour or rewrite the terminal).
TEST(InputError, NamesFromTheFileAreEscaped) {
  InputError error({.file = "a.ply",
                    .line = 3,
                    .element = "vert\x1b[2Jex\x04",
                    .property = "b\x90\xc2\x9b\xc3\xb6\xc3",
                    .expected = "a number",
                    .found = "properties a\tb\x7f"});
  EXPECT_STREQ(error.what(),
               "a.ply: line 3, element 'vert\\x1b[2Jex\\x04', property "
               "'b\\x90\\xc2\\x9b\xc3\xb6\\xc3': expected a number, found "
               "properties a\\x09b\\x7f");
}

TEST(InputError, LongNamesAreCut) {
  const std::string name(200, 'n');
  InputError error({.file = "a.pcd", .property = name, .expected = "a type"});
  EXPECT_EQ(std::string(error.what()),
            "a.pcd: property '" + std::string(120, 'n') + "...': expected a type");
}

TEST(QuoteInput, EscapesControlBytesAndTruncates) {
  EXPECT_EQ(quoteInput("ab\x01"
                       "c"),
            "'ab\\x01c'");
  EXPECT_EQ(quoteInput("abcdef", 3), "'abc...'");
  EXPECT_EQ(quoteInput("it's"), "'it\\x27s'");
}

}  // namespace
}  // namespace parallax
