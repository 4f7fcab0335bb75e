// libFuzzer target for the LAS reader: any bytes must give a cloud or an InputError, never a
// crash, an out-of-bounds read or an allocation beyond what the input's size justifies.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/error.h"
#include "io/las_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    parallax::PointCloud cloud =
        parallax::readLasFromMemory(bytes, "fuzz.las", {.parallel = false});
    (void)cloud;
  } catch (const parallax::InputError&) {
  }
  return 0;
}
