// Embedded GLSL sources of the point pass (see point_pass_glsl.cpp), and the colour functions the
// compute rasterizer shares with it.
#pragma once

#include <string>

#include "render/render_settings.h"

namespace parallax::glsl {

// The value of the COLOR_MODE define that both rasterizers' shaders take for `mode`.
int colorModeDefine(ColorMode mode);

// ramp(), classColor() and, with FILTER, keepPoint(): both rasterizers' colour and filter code,
// inserted after the #defines, so that a colour mode looks the same whoever draws it.
const std::string& pointShadingFunctions();
extern const char* const kPointVertex;
extern const char* const kPointFragment;

}  // namespace parallax::glsl
