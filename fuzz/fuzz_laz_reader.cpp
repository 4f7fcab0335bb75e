// libFuzzer target for the LAZ reader: any bytes must give a cloud or an InputError, never a
// crash, an out-of-bounds read, a hang or an allocation beyond what the input's size justifies.
// Every chunk is decoded (on one thread, so that a failure reproduces exactly), and the chunk
// reader and the preview's path through the chunks are taken too.
#include <cstddef>
#include <cstdint>
#include <span>

#include "core/error.h"
#include "io/laz_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  try {
    parallax::PointCloud cloud =
        parallax::readLazFromMemory(bytes, "fuzz.laz", {.parallel = false});
    (void)cloud;
  } catch (const parallax::InputError&) {
  }
  return 0;
}
