#include "render/filter_uniforms.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <utility>
#include <vector>

#include "render/rasterizer.h"

namespace parallax {
namespace {

// A chunk-relative float bound, kept finite (a bound of 1e300 must not turn into inf - inf).
float relative(double value, double origin) {
  return float(std::clamp(value - origin, -double(FLT_MAX), double(FLT_MAX)));
}

// The (hi, lo) split of a bound, lo rounded up (a minimum) or down (a maximum) to a float, so
// that a point's exact pair compares with it as its double does with the bound.
std::array<float, 2> splitBound(double d, bool minimum) {
  d = std::clamp(d, -1e30, 1e30);
  const float hi = float(d);
  const double rest = d - double(hi);  // exact: hi is d's leading bits
  float lo = float(rest);
  if (minimum && double(lo) < rest) lo = std::nextafter(lo, INFINITY);
  if (!minimum && double(lo) > rest) lo = std::nextafter(lo, -INFINITY);
  return {hi, lo};
}

}  // namespace

unsigned filterParts(const PointFilter& filter, const DrawSet& draw_set) {
  unsigned parts = 0;
  if (!filter.keepsEveryClass()) parts |= kFilterClasses;
  if (!filter.keepsEveryReturn()) parts |= kFilterReturns;
  // A GPS range where there is no GPS time keeps all or nothing: the latter is an empty
  // intensity range.
  if (filter.intensity || (filter.gps_time && !draw_set.has_gps_time)) parts |= kFilterIntensity;
  if (filter.elevation) parts |= kFilterElevation;
  if (filter.gps_time && draw_set.has_gps_time) parts |= kFilterGps;
  if (!filter.clip_planes.empty()) parts |= kFilterPlanes;
  if (!filter.polygon.empty()) parts |= kFilterPolygon;
  if (filter.clip_highlight && filter.hasRegion()) parts |= kFilterHighlight;
  return parts;
}

std::string filterDefines(unsigned parts) {
  std::string text = "#define FILTER " + std::to_string(int(parts != 0)) + "\n";
  const std::pair<FilterPart, const char*> names[] = {{kFilterClasses, "FILTER_CLASSES"},
                                                      {kFilterReturns, "FILTER_RETURNS"},
                                                      {kFilterIntensity, "FILTER_INTENSITY"},
                                                      {kFilterElevation, "FILTER_ELEVATION"},
                                                      {kFilterGps, "FILTER_GPS"},
                                                      {kFilterPlanes, "FILTER_PLANES"},
                                                      {kFilterPolygon, "FILTER_POLYGON"},
                                                      {kFilterHighlight, "FILTER_HIGHLIGHT"}};
  for (const auto& [part, name] : names) {
    text += "#define " + std::string(name) + " " + std::to_string(int((parts & part) != 0)) + "\n";
  }
  return text;
}

std::array<std::uint32_t, 2> filterIntensityBounds(const PointFilter& filter,
                                                   const DrawSet& draw_set) {
  constexpr std::array<std::uint32_t, 2> kAll{0, 65535}, kNone{1, 0};
  // A GPS range on a draw set without GPS time is decided here (every point has time 0); an
  // empty intensity range is how the shaders are told to keep nothing.
  if (filter.gps_time && !draw_set.has_gps_time && !filter.gps_time->contains(0.0)) return kNone;
  if (!filter.intensity) return kAll;
  if (!draw_set.has_intensity) return filter.intensity->contains(0.0) ? kAll : kNone;
  double lo = filter.intensity->min, hi = filter.intensity->max;
  if (draw_set.intensity_integral) lo = std::ceil(lo), hi = std::floor(hi);
  if (lo > hi || lo > draw_set.intensity_max || hi < draw_set.intensity_min) return kNone;
  ChunkLayout layout;
  layout.intensity_min = draw_set.intensity_min, layout.intensity_max = draw_set.intensity_max;
  const auto quantized = [&](double v) {
    return quantizeIntensity(float(std::clamp(v, -double(FLT_MAX), double(FLT_MAX))), layout);
  };
  return {quantized(lo), quantized(hi)};
}

std::array<float, 4> filterGpsBounds(const ValueRange& range, double base) {
  const auto lo = splitBound(range.min - base, true), hi = splitBound(range.max - base, false);
  return {lo[0], lo[1], hi[0], hi[1]};
}

FilterUniforms::FilterUniforms(const ShaderProgram& program, const PointFilter& filter,
                               const DrawSet& draw_set)
    : filter_(filter), parts_(filterParts(filter, draw_set)), gps_on_((parts_ & kFilterGps) != 0) {
  const auto class_words = filterClassWords(filter, draw_set.has_classification);
  glUniform1uiv(program.uniform("u_filter_classes"), 8, class_words.data());
  glUniform1uiv(program.uniform("u_filter_returns"), 8, filter.returns.data());
  const auto intensity = filterIntensityBounds(filter, draw_set);
  glUniform2ui(program.uniform("u_filter_intensity"), intensity[0], intensity[1]);
  glUniform1i(program.uniform("u_clip_outside"), GLint(filter.clip_outside));
  glUniform1i(program.uniform("u_clip_plane_count"),
              GLint(std::min(filter.clip_planes.size(), PointFilter::kMaxClipPlanes)));
  glUniform1i(program.uniform("u_clip_polygon_count"),
              GLint(std::min(filter.polygon.size(), PointFilter::kMaxGpuPolygonVertices)));
  planes_ = program.uniform("u_clip_planes");
  elevation_ = program.uniform("u_filter_elevation");
  gps_ = program.uniform("u_filter_gps");
  polygon_ = program.uniform("u_clip_polygon");
}

void FilterUniforms::setChunk(const PointChunk& chunk) const {
  if (parts_ & kFilterPlanes) {
    const auto planes = chunkClipPlanes(filter_, chunk.origin);
    glUniform4fv(planes_, GLsizei(PointFilter::kMaxClipPlanes), planes.data());
  }
  if (filter_.elevation) {
    const double z = chunk.origin.z;
    glUniform2f(elevation_, relative(filter_.elevation->min, z),
                relative(filter_.elevation->max, z));
  }
  if (gps_on_) {
    const auto bounds = filterGpsBounds(*filter_.gps_time, chunk.gps_base);
    glUniform4fv(gps_, 1, bounds.data());
  }
  if (!filter_.polygon.empty()) {
    // Two vertices a vec4; the origin taken off in double, as for the positions.
    const std::size_t n = std::min(filter_.polygon.size(), PointFilter::kMaxGpuPolygonVertices);
    std::vector<float> vertices(2 * n + 2, 0.0f);
    for (std::size_t i = 0; i < n; ++i) {
      vertices[2 * i] = relative(filter_.polygon[i][0], chunk.origin.x);
      vertices[2 * i + 1] = relative(filter_.polygon[i][1], chunk.origin.y);
    }
    glUniform4fv(polygon_, GLsizei((n + 1) / 2), vertices.data());
  }
}

}  // namespace parallax
