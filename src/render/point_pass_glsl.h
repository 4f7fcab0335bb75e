// Embedded GLSL sources of the point pass (see point_pass_glsl.cpp), and the colour functions the
// compute rasterizer shares with it.
#pragma once

namespace parallax::glsl {

// ramp(), classColor() and, with FILTER, keepPoint(): both rasterizers' colour and filter code.
extern const char* const kPointShadingFunctions;
extern const char* const kPointVertex;
extern const char* const kPointFragment;

}  // namespace parallax::glsl
