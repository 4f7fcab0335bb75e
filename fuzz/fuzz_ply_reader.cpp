// libFuzzer target for the PLY reader: any bytes either read as a PointCloud or raise
// parallax::InputError. Anything else (another exception, a crash, a sanitizer report, a timeout,
// an allocation beyond -rss_limit_mb) is a bug the fuzzer reports.
//
// Both decode paths run on every input: the serial one and the parallel (TBB) one, which split
// the body differently and so have their own boundary cases. When both succeed they must agree.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <span>

#include "core/error.h"
#include "core/point_cloud.h"
#include "io/ply_reader.h"

namespace {

std::optional<parallax::PointCloud> readOrReject(std::span<const std::byte> bytes, bool parallel) {
  parallax::PlyReadOptions options;
  options.parallel = parallel;
  try {
    return parallax::readPlyFromMemory(bytes, "fuzz.ply", options);
  } catch (const parallax::InputError&) {
    return std::nullopt;  // rejected with a message: the expected outcome for bad input
  }
}

// Aborts (so the fuzzer saves the input) when the two reads disagree on what they read.
void checkSame(const parallax::PointCloud& a, const parallax::PointCloud& b) {
  bool same = a.count == b.count && a.quantization == b.quantization &&
              a.positions.size() == b.positions.size() && a.colors.size() == b.colors.size() &&
              a.normals.size() == b.normals.size() && a.scalars.size() == b.scalars.size();
  if (same && !a.positions.empty()) {
    same = std::memcmp(a.positions.data(), b.positions.data(),
                       a.positions.size() * sizeof(parallax::Int3)) == 0;
  }
  if (!same) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  auto serial = readOrReject(bytes, false);
  auto parallel = readOrReject(bytes, true);
  // One path accepting what the other rejects is a bug too.
  if (serial.has_value() != parallel.has_value()) std::abort();
  if (serial && parallel) checkSame(*serial, *parallel);
  return 0;
}
