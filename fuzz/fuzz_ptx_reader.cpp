// libFuzzer target for the PTX reader: any bytes must give a cloud or an InputError, never a
// crash, a hang or an out-of-bounds read (scan headers announcing more points than there are
// lines, truncated transforms, point lines of the wrong size).
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/error.h"
#include "io/ptx_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    parallax::PointCloud cloud = parallax::readPtxFromMemory(bytes, "fuzz.ptx");
    (void)cloud;
  } catch (const parallax::InputError&) {
  }
  return 0;
}
