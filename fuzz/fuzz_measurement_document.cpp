// libFuzzer target for the measurement file reader: any bytes give a document or an InputError;
// never a crash, another exception type, or a hang. A document read is written and read again
// and must come back the same (the writer's output is always readable).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string_view>

#include "core/error.h"
#include "measure/measurement_document.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  parallax::MeasurementDocument document;
  try {
    document = parallax::parseMeasurementDocument(text, "fuzz.json");
  } catch (const parallax::InputError&) {
    return 0;
  }
  const std::string written = parallax::measurementDocumentToJson(document).dump();
  const parallax::MeasurementDocument again =
      parallax::parseMeasurementDocument(written, "fuzz.json");
  if (again.measurements != document.measurements) std::abort();
  return 0;
}
