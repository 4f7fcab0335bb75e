// libFuzzer target for the text (XYZ/CSV/PTS) reader: any bytes must give a cloud or an
// InputError, never a crash or an out-of-bounds read. The first byte picks the PTS mode, so the
// count-line paths are reached too.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/error.h"
#include "io/text_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  bool pts = (data[0] & 1) != 0;
  std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data + 1), size - 1);
  try {
    parallax::PointCloud cloud = parallax::readTextFromMemory(bytes, pts ? "fuzz.pts" : "fuzz.xyz",
                                                              {.parallel = false, .pts = pts});
    (void)cloud;
  } catch (const parallax::InputError&) {
  }
  return 0;
}
