// libFuzzer target for the PTS reader: its count-line check, then the text reader in PTS mode;
// any bytes must give a cloud or an InputError.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/error.h"
#include "io/pts_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    parallax::PointCloud cloud =
        parallax::readPtsFromMemory(bytes, "fuzz.pts", {.parallel = false});
    (void)cloud;
  } catch (const parallax::InputError&) {
  }
  return 0;
}
