// libFuzzer target for the PCD reader: any bytes must give a cloud or an InputError, never a
// crash, an out-of-bounds read or an allocation the bytes do not justify. The three encodings
// (ascii, binary, binary_compressed with its LZF) are reached from the seeds.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/error.h"
#include "io/pcd_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    parallax::PointCloud cloud =
        parallax::readPcdFromMemory(bytes, "fuzz.pcd", {.parallel = false});
    (void)cloud;
  } catch (const parallax::InputError&) {
  }
  return 0;
}
