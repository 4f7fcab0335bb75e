// Everything a user can change about how points are drawn; one struct shared by `parallax render`,
// the viewer's panel and the tests.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/attribute_selection.h"
#include "core/point_filter.h"
#include "render/scalar_colors.h"

namespace parallax {

enum class PointSizeMode {
  Fixed,       // `point_size_px` pixels
  Attenuated,  // `world_size` world units, smaller with distance
  Adaptive,    // `adaptive_scale` times the local point spacing, in world units
};
enum class PointShape { Square, Round };
enum class ColorMode { Rgb, Elevation, Intensity, Normal, Classification, Uniform };
// Who turns points into pixels (render/rasterizer.h). Auto: the compute rasterizer wherever it
// supports the frame's settings, GL_POINTS elsewhere.
enum class RasterizerKind { Points, Compute, Auto };

struct RenderSettings {
  PointSizeMode size_mode = PointSizeMode::Fixed;
  float point_size_px = 1.0f;
  float world_size = 0.05f;
  float adaptive_scale = 1.5f;
  float min_size_px = 1.0f, max_size_px = 64.0f;  // clamp of the distance-dependent sizes
  PointShape shape = PointShape::Square;
  ColorMode color = ColorMode::Rgb;
  // A scalar attribute's colours (render/scalar_colors.h): with a field, the cloud is uploaded
  // with the ramp's colours in place of its own and `color` is Rgb.
  ScalarColoring scalar;
  std::array<float, 3> uniform_color{1.0f, 1.0f, 1.0f};  // 0..1
  std::array<float, 3> background{0.0f, 0.0f, 0.0f};     // 0..1
  bool lighting = false;       // head-light Lambert from normals (ignored without normals)
  bool edl = false;            // eye-dome lighting post pass
  float edl_strength = 1.0f;   // 0 = none
  float edl_radius_px = 1.4f;  // neighbour distance in pixels
  // Multisampling: 0 or 1 is off (every pixel is a point's colour or the background, which the
  // exact 1-pixel mode needs); 2, 4 or 8 samples per pixel, clamped to what the GPU offers.
  int samples = 0;
  RasterizerKind rasterizer = RasterizerKind::Auto;
  // High quality (compute rasterizer only): each pixel blends the colours of all points within
  // `hq_depth_range` (relative eye depth) of the front-most one, Potree's HQ splats and
  // Schuetz's HQS, which removes the shimmer of 1-pixel points in motion.
  bool hq = false;
  float hq_depth_range = 0.01f;
  // Which points are drawn at all (core/point_filter.h), tested per point in both rasterizers'
  // shaders; changing it changes uniforms only, never the uploaded buffers. The default keeps
  // every point and compiles to nothing.
  PointFilter filter;

  friend bool operator==(const RenderSettings&, const RenderSettings&) = default;
};

// Which parts of the look the viewer chooses for each cloud it opens: those the user left open
// (`parallax view` without --size-mode, --point-size or --shape: the size; without --lighting:
// the lighting).
struct ViewerLookChoice {
  bool size = false;
  bool lighting = false;
};

// What the viewer needs to know of a cloud to choose its look.
struct LookTraits {
  bool spacing_known = false;  // a local spacing (a whole cloud's, or an octree's) is known
  bool has_normals = false;
};

// The viewer's look: `settings` with, where `choice` leaves it to the viewer, round points sized
// to the local spacing (adaptive) where the spacing is known (otherwise `asked`'s size mode and
// shape), and lighting exactly where the cloud has normals. `asked` is what the options gave
// before any cloud was opened, so that a second cloud without a known spacing does not keep the
// first one's choice. Round discs of the local spacing close a scanned surface without the blocky
// look squares of that size have where the scan is sparse. `parallax view` (through the viewer)
// and `parallax bench render --look viewer` both call this: the figures watch what people see.
RenderSettings viewerLook(RenderSettings settings, const RenderSettings& asked,
                          ViewerLookChoice choice, LookTraits traits);

// The attributes a picture with these settings needs, by the model's names: what the colour
// mode shows (colour, intensity, classification, the normals), a scalar colouring's field, the
// normals the lighting uses, and what the filter tests (classes, returns, intensity, GPS time).
// Positions are always read. `render` asks a LAZ or COPC reader for these only, and `view` an
// octree's nodes (core/attribute_selection.h).
AttributeSelection attributesDrawn(const RenderSettings& settings);

// "rgb", "elevation", ... ; std::nullopt for an unknown name.
std::optional<ColorMode> parseColorMode(std::string_view name);
std::optional<PointSizeMode> parsePointSizeMode(std::string_view name);
std::optional<PointShape> parsePointShape(std::string_view name);
std::string_view colorModeName(ColorMode mode);
std::string_view pointSizeModeName(PointSizeMode mode);
std::string_view pointShapeName(PointShape shape);
std::optional<RasterizerKind> parseRasterizerKind(std::string_view name);  // points|compute|auto
std::string_view rasterizerKindName(RasterizerKind kind);
// "rgb|elevation|intensity|normal|classification|uniform", for help texts and errors.
std::string colorModeNames();

}  // namespace parallax
