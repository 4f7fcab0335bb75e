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

TEST(QuoteInput, EscapesControlBytesAndTruncates) {
  EXPECT_EQ(quoteInput("ab\x01"
                       "c"),
            "'ab\\x01c'");
  EXPECT_EQ(quoteInput("abcdef", 3), "'abc...'");
  EXPECT_EQ(quoteInput("it's"), "'it\\x27s'");
}

}  // namespace
}  // namespace parallax
