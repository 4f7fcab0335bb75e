// The measurement file: a camera, the measurements and the annotations, as JSON. `parallax view`
// saves and loads it; `view --measurements FILE` and `render --measurements FILE` read it.
//
//   {
//     "format": "parallax-measurements", "version": 1,
//     "camera": {...},                            optional; as render/camera.h cameraToJson
//     "measurements": [                           optional; in order
//       {"kind": "distance", "name": "ridge", "points": [[x, y, z], ...]},
//       {"kind": "profile", "points": [[x, y, z], ...], "width": 2.5},
//       ...
//     ],
//     "annotations": [                            optional
//       {"label": "antenna", "position": [x, y, z], "camera": {...}}
//     ]
//   }
//
// Kinds and their vertex counts: point 1, height 2, angle 3, distance and profile at least 2,
// area at least 3 (measure/measurement.h). Coordinates are world coordinates written with 17
// significant digits, so a file read back gives the same doubles. "name" and an annotation's
// "camera" are optional; "width" is the profile's corridor width (> 0), required for a profile
// and not allowed on other kinds. Unknown keys are an error (a misspelt "widht" would otherwise
// be silently dropped).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "measure/measurement.h"
#include "render/camera.h"

namespace parallax {

struct MeasurementDocument {
  std::optional<Camera> camera;
  std::vector<Measurement> measurements;
  std::vector<Annotation> annotations;
  friend bool operator==(const MeasurementDocument&, const MeasurementDocument&) = default;
};

nlohmann::json measurementDocumentToJson(const MeasurementDocument& document);

// Parses `text` (the contents of `file`, named in errors). Throws InputError naming the file,
// the JSON path of the offending value ("measurements[2].points[1]"), what was expected and
// what was found; a syntax error names the line and column.
MeasurementDocument parseMeasurementDocument(std::string_view text, const std::string& file);
// Reads `path`; a missing or unreadable file is an InputError too.
MeasurementDocument loadMeasurementDocument(const std::filesystem::path& path);
// Writes under a temporary name beside `path` and renames it, so an existing file is replaced
// whole or not at all. Throws std::runtime_error naming the file on failure.
void saveMeasurementDocument(const MeasurementDocument& document,
                             const std::filesystem::path& path);

}  // namespace parallax
