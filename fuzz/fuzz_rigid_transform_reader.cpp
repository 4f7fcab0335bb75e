// libFuzzer target for `parallax register --init FILE` (parseRigidTransform): any bytes must give
// a finite rigid transform (last row 0 0 0 1, a rotation) or an InputError, never a crash.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "registration/rigid_transform.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const parallax::RigidTransform t = parallax::parseRigidTransform(text, "fuzz.txt");
    for (const auto& row : t.m) {
      for (double v : row) {
        if (!std::isfinite(v)) std::abort();
      }
    }
    if (t.m[3][3] != 1.0 || std::abs(t.angleDegrees()) > 180.0) std::abort();
  } catch (const parallax::InputError&) {
  }
  return 0;
}
