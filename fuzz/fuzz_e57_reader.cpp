// libFuzzer target for the E57 reader: any bytes must give a cloud or an InputError, never a
// crash, an out-of-bounds read or an allocation beyond what the file's size justifies. The
// checksums would stop almost every mutation at the first page, so the target reseals every
// page (CRC-32C) before reading when the first byte is odd: the XML and packet parsers are
// reached with mutated bytes too.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/error.h"
#include "io/e57/e57_pages.h"
#include "io/e57/e57_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const bool reseal = (data[0] & 1) != 0;
  std::vector<std::byte> bytes(reinterpret_cast<const std::byte*>(data + 1),
                               reinterpret_cast<const std::byte*>(data + size));
  if (reseal) {
    for (std::size_t page = 0; page + parallax::kE57PageSize <= bytes.size();
         page += parallax::kE57PageSize) {
      const std::uint32_t crc = parallax::crc32c({bytes.data() + page, parallax::kE57PageData});
      for (int i = 0; i < 4; ++i) {
        bytes[page + parallax::kE57PageData + std::size_t(i)] = std::byte(crc >> (24 - 8 * i));
      }
    }
  }
  try {
    parallax::PointCloud cloud = parallax::readE57FromMemory(bytes, "fuzz.e57");
    (void)cloud;
  } catch (const parallax::InputError&) {
  }
  return 0;
}
