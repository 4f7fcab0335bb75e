// GLSL of the point pass, kept beside the pass (point_pass.cpp) that binds its inputs.
#include "render/point_pass_glsl.h"

#include <array>
#include <cstdio>
#include <string>

#include "render/class_colors.h"

namespace parallax::glsl {

int colorModeDefine(ColorMode mode) {
  switch (mode) {
    case ColorMode::Rgb:
      return 0;
    case ColorMode::Elevation:
      return 1;
    case ColorMode::Intensity:
      return 2;
    case ColorMode::Normal:
      return 3;
    case ColorMode::Classification:
      return 4;
    case ColorMode::Uniform:
      return 5;
  }
  return 5;
}

namespace {

const char* const kRamp = R"glsl(
// A perceptually ordered ramp (dark blue, cyan, green, yellow, red, white-ish) for elevation.
vec3 ramp(float t) {
  const vec3 stops[6] = vec3[6](vec3(0.19, 0.07, 0.46), vec3(0.12, 0.56, 0.86),
                                vec3(0.20, 0.78, 0.39), vec3(0.95, 0.85, 0.20),
                                vec3(0.90, 0.30, 0.12), vec3(0.98, 0.92, 0.88));
  float x = clamp(t, 0.0, 1.0) * 5.0;
  int i = min(int(x), 4);
  return mix(stops[i], stops[i + 1], x - float(i));
}
)glsl";

const char* const kFilter = R"glsl(
// The point filter (PointFilter), its uniforms set by FilterUniforms (filter_uniforms.h, which
// says how each test agrees with the CPU's): classes and returns as 8 words of bits each, the
// unorm16 intensity bounds, elevation, clip planes and polygon in chunk-relative coordinates
// (the chunk origin taken off in double on the CPU), GPS time as (hi, lo) pairs relative to the
// chunk's base. `word` is the extras' first word: intensity | class << 16 | returns << 24, the
// returns byte being return number | number of returns << 4 (= the returns table's index). The
// region is the planes' and polygon's intersection; u_clip_outside keeps its complement.
#if FILTER
uniform uint u_filter_classes[8];
uniform uint u_filter_returns[8];
uniform uvec2 u_filter_intensity;
uniform vec2 u_filter_elevation;
uniform vec4 u_filter_gps;  // min (hi, lo), max (hi, lo)
uniform vec4 u_clip_planes[6];
uniform int u_clip_plane_count;
uniform vec4 u_clip_polygon[128];  // two vertices (x, y) a vec4
uniform int u_clip_polygon_count;
uniform bool u_clip_outside;

#if FILTER_POLYGON
vec2 polygonVertex(int i) {
  vec4 pair = u_clip_polygon[i >> 1];
  return (i & 1) == 0 ? pair.xy : pair.zw;
}

// Crossing number, the expression of PointFilter::insidePolygon.
bool insidePolygon(vec2 p) {
  bool inside = false;
  vec2 b = polygonVertex(u_clip_polygon_count - 1);
  for (int i = 0; i < u_clip_polygon_count; ++i) {
    vec2 a = polygonVertex(i);
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) {
      inside = !inside;
    }
    b = a;
  }
  return inside;
}
#endif

#if FILTER_PLANES || FILTER_POLYGON
// The planes' and polygon's intersection (PointFilter::inRegion).
bool inClipRegion(vec3 position) {
  bool inside = true;
#if FILTER_PLANES
  for (int i = 0; i < u_clip_plane_count; ++i) {
    if (dot(u_clip_planes[i].xyz, position) + u_clip_planes[i].w < 0.0) {
      inside = false;
      break;
    }
  }
#endif
#if FILTER_POLYGON
  if (inside) inside = insidePolygon(position.xy);
#endif
  return inside;
}
#endif

// Only the parts the frame uses are compiled in (FILTER_*, filter_uniforms.h).
bool keepPoint(vec3 position, uint word, vec2 gps) {
#if FILTER_CLASSES
  uint c = (word >> 16) & 0xffu;
  if (((u_filter_classes[c >> 5] >> (c & 31u)) & 1u) == 0u) return false;
#endif
#if FILTER_RETURNS
  uint r = word >> 24;
  if (((u_filter_returns[r >> 5] >> (r & 31u)) & 1u) == 0u) return false;
#endif
#if FILTER_INTENSITY
  uint q = word & 0xffffu;
  if (q < u_filter_intensity.x || q > u_filter_intensity.y) return false;
#endif
#if FILTER_ELEVATION
  if (position.z < u_filter_elevation.x || position.z > u_filter_elevation.y) return false;
#endif
#if FILTER_GPS
  // Pairs compared hi first: exact, where one float would merge steps below 64 s at 1e9 s.
  bool above = gps.x > u_filter_gps.x || (gps.x == u_filter_gps.x && gps.y >= u_filter_gps.y);
  bool below = gps.x < u_filter_gps.z || (gps.x == u_filter_gps.z && gps.y <= u_filter_gps.w);
  if (!above || !below) return false;
#endif
#if (FILTER_PLANES || FILTER_POLYGON) && !FILTER_HIGHLIGHT
  return inClipRegion(position) != u_clip_outside;
#else
  return true;
#endif
}

#if FILTER_HIGHLIGHT
// --clip-mode highlight: the region's points are drawn half way to this colour.
const vec3 kHighlightColor = vec3(1.0, 0.25, 0.05);
vec3 highlighted(vec3 color, vec3 position) {
  return inClipRegion(position) ? mix(color, kHighlightColor, 0.5) : color;
}
#endif
#endif
)glsl";

// classColor() with the palette of render/class_colors.h, so that the picture and the viewer's
// legend cannot disagree.
std::string classColorFunction() {
  std::string text = "vec3 classColor(uint c) {\n  const vec3 table[" +
                     std::to_string(kPaletteClasses) + "] = vec3[" +
                     std::to_string(kPaletteClasses) + "](";
  for (std::size_t c = 0; c < kPaletteClasses; ++c) {
    const std::array<float, 3> rgb = classColor(int(c));
    char entry[64];
    // Nine significant digits give back the float exactly; '#' keeps the decimal point.
    std::snprintf(entry, sizeof entry, "%svec3(%#.9g, %#.9g, %#.9g)", c ? ", " : "", double(rgb[0]),
                  double(rgb[1]), double(rgb[2]));
    text += entry;
  }
  const std::array<float, 3> other = classColor(int(kPaletteClasses));
  char fallback[96];
  std::snprintf(fallback, sizeof fallback,
                ");\n  return c < %zuu ? table[c] : vec3(%#.9g, %#.9g, %#.9g);\n}\n",
                kPaletteClasses, double(other[0]), double(other[1]), double(other[2]));
  return text + fallback;
}

}  // namespace

const std::string& pointShadingFunctions() {
  static const std::string text = std::string(kRamp) + classColorFunction() + kFilter;
  return text;
}

const char* const kPointVertex = R"glsl(#version 450 core
layout(location = 0) in vec3 a_position;   // relative to the chunk origin
layout(location = 1) in vec4 a_color;
layout(location = 2) in vec4 a_normal;
layout(location = 3) in float a_intensity;  // 0..1 over the cloud's range
layout(location = 4) in uint a_classification;
layout(location = 5) in float a_spacing;    // local point spacing, world units
layout(location = 6) in uint a_filter_word;  // the extras' first word (keepPoint)
layout(location = 7) in vec2 a_gps;          // GPS time (hi, lo) relative to the chunk's base

uniform mat4 u_model_view;      // chunk to eye: world-to-eye with the chunk origin folded in
uniform mat4 u_projection;
// Variants are compiled per mode (PointPass prepends the #defines): llvmpipe runs every side of a
// branch on a uniform under a mask, so run-time switches would cost every mode's work per point.
//   COLOR_MODE  0 rgb, 1 elevation, 2 intensity, 3 normal, 4 classification, 5 uniform
//   SIZE_MODE   0 fixed, 1 attenuated, 2 adaptive
//   LIGHTING, ORTHOGRAPHIC, FILTER  0 or 1
uniform vec3 u_uniform_color;
uniform vec2 u_elevation;       // t = (z + x) * y: chunk z to 0..1 over the cloud
uniform float u_size_px;
uniform float u_world_size;
uniform float u_adaptive_scale;
uniform float u_node_spacing;   // > 0: a level-of-detail node's spacing replaces a_spacing
uniform vec2 u_size_clamp;
uniform float u_pixels_per_unit; // perspective: at eye depth 1; orthographic: everywhere

out vec4 v_color;
out float v_depth;

void main() {
#if FILTER
  if (!keepPoint(a_position, a_filter_word, a_gps)) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: the point is dropped
    gl_PointSize = 1.0;
    v_color = vec4(0.0);
    v_depth = 0.0;
    return;
  }
#endif
  vec4 eye = u_model_view * vec4(a_position, 1.0);
  gl_Position = u_projection * eye;
#if ORTHOGRAPHIC
  v_depth = -eye.z;
#else
  v_depth = max(-eye.z, 0.0);
#endif

#if COLOR_MODE == 0
  vec3 color = a_color.rgb;
#elif COLOR_MODE == 1
  vec3 color = ramp((a_position.z + u_elevation.x) * u_elevation.y);
#elif COLOR_MODE == 2
  vec3 color = vec3(a_intensity);
#elif COLOR_MODE == 3
  vec3 color = normalize(a_normal.xyz) * 0.5 + 0.5;
#elif COLOR_MODE == 4
  vec3 color = classColor(a_classification);
#else
  vec3 color = u_uniform_color;
#endif
#if FILTER && FILTER_HIGHLIGHT
  color = highlighted(color, a_position);
#endif

#if LIGHTING
  // Head-light Lambert: the light sits in the eye. Two-sided, because scanners' normals point
  // either way.
  vec3 n = normalize(mat3(u_model_view) * a_normal.xyz);
#if ORTHOGRAPHIC
  vec3 to_eye = vec3(0.0, 0.0, 1.0);
#else
  vec3 to_eye = normalize(-eye.xyz);
#endif
  color *= 0.2 + 0.8 * abs(dot(n, to_eye));
#endif
  v_color = vec4(color, 1.0);

#if SIZE_MODE == 0
  gl_PointSize = u_size_px;
#else
#if SIZE_MODE == 1
  float world = u_world_size;
#else
  // A select on a uniform, not a branch: both operands are at hand anyway.
  float world = (u_node_spacing > 0.0 ? u_node_spacing : a_spacing) * u_adaptive_scale;
#endif
#if ORTHOGRAPHIC
  float per_unit = u_pixels_per_unit;
#else
  float per_unit = u_pixels_per_unit / max(-eye.z, 1e-9);
#endif
  gl_PointSize = world > 0.0 ? clamp(world * per_unit, u_size_clamp.x, u_size_clamp.y) : u_size_px;
#endif
}
)glsl";

const char* const kPointFragment = R"glsl(#version 450 core
// Variants: ROUND (discard outside the disc), EYE_DEPTH (write linear depth for eye-dome
// lighting into the second attachment, with a coverage of 1 beside it: a multisample resolve
// averages both, and their ratio is the mean depth of the samples a point covered).
in vec4 v_color;
in float v_depth;
layout(location = 0) out vec4 out_color;
#if EYE_DEPTH
layout(location = 1) out vec2 out_depth;
#endif

void main() {
#if ROUND
  vec2 d = gl_PointCoord - vec2(0.5);
  if (dot(d, d) > 0.25) discard;
#endif
  out_color = v_color;
#if EYE_DEPTH
  out_depth = vec2(v_depth, 1.0);
#endif
}
)glsl";

}  // namespace parallax::glsl
