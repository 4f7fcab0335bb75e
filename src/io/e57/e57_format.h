// E57's row of the format table (io/point_format.h): detection by the "ASTM-E57" signature, the
// header from the XML section, whole and streamed reads, the preview, `info`'s account of the
// scans and images, and the writer.
#pragma once

#include "io/point_format.h"

namespace parallax {

PointFormatEntry e57Format();

}  // namespace parallax
