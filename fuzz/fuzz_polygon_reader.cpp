// libFuzzer target for the --clip-polygon reader (GeoJSON and "x y" text): any bytes must give a
// polygon of at least 3 finite vertices or an InputError, never a crash.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "core/error.h"
#include "io/polygon_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const parallax::Polygon2 polygon = parallax::parsePolygon(text, "fuzz.geojson");
    if (polygon.size() < 3) std::abort();
    for (const auto& v : polygon) {
      if (!std::isfinite(v[0]) || !std::isfinite(v[1])) std::abort();
    }
  } catch (const parallax::InputError&) {
  }
  return 0;
}
