// Embedded GLSL sources of the compute rasterizer (see compute_rasterizer_glsl.cpp). Each has a
// `//@DEFINES@` line where the variant's #defines (and the shared colour functions) go.
#pragma once

namespace parallax::glsl {

extern const char* const kComputeRasterizer;
extern const char* const kComputeResolve;
extern const char* const kLargeSplatArgs;

}  // namespace parallax::glsl
