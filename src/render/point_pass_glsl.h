// Embedded GLSL sources of the point pass (see point_pass_glsl.cpp).
#pragma once

namespace parallax::glsl {

extern const char* const kPointVertex;
extern const char* const kPointFragment;

}  // namespace parallax::glsl
