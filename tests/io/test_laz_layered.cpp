// The layered chunk codec of LAZ (compressor 3, point formats 6-10).
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/laz/layered_codec.h"
#include "laz_test_file.h"

namespace parallax::laz {
namespace {

using testing::fnv1a64;
using testing::LazTestFile;
using testing::readLazTestFile;

const std::string kDataDir = PARALLAX_LAZ_TEST_DATA;

std::vector<std::byte> decodeAll(const LazTestFile& f) {
  auto decoder = makeLayeredDecoder(f.vlr.items);
  EXPECT_EQ(decoder->recordLength(), f.record_length);
  std::vector<std::byte> records(f.point_count * f.record_length);
  std::size_t at = 0;
  for (const auto& c : f.chunks) {
    decoder->decode(f.chunkBytes(c), c.points, records.data() + at);
    at += c.points * f.record_length;
  }
  return records;
}

TEST(LazLayered, DecodesCopcFiles) {
  for (const char* name : {"simple.copc.laz", "ellipsoid.copc.laz"}) {
    const LazTestFile f = readLazTestFile(kDataDir + "/" + name);
    const std::vector<std::byte> records = decodeAll(f);
    printf("%s %zu 0x%016llx\n", name, records.size(), (unsigned long long)fnv1a64(records));
  }
}

}  // namespace
}  // namespace parallax::laz
