#include "render/render_settings.h"

#include "core/column_names.h"
#include "core/filter_attributes.h"

namespace parallax {

namespace {

constexpr std::array<std::pair<ColorMode, std::string_view>, 6> kColorModes{{
    {ColorMode::Rgb, "rgb"},
    {ColorMode::Elevation, "elevation"},
    {ColorMode::Intensity, "intensity"},
    {ColorMode::Normal, "normal"},
    {ColorMode::Classification, "classification"},
    {ColorMode::Uniform, "uniform"},
}};
constexpr std::array<std::pair<PointSizeMode, std::string_view>, 3> kSizeModes{{
    {PointSizeMode::Fixed, "fixed"},
    {PointSizeMode::Attenuated, "attenuated"},
    {PointSizeMode::Adaptive, "adaptive"},
}};
constexpr std::array<std::pair<PointShape, std::string_view>, 2> kShapes{{
    {PointShape::Square, "square"},
    {PointShape::Round, "round"},
}};

constexpr std::array<std::pair<RasterizerKind, std::string_view>, 3> kRasterizers{{
    {RasterizerKind::Points, "points"},
    {RasterizerKind::Compute, "compute"},
    {RasterizerKind::Auto, "auto"},
}};

template <class T, std::size_t N>
std::optional<T> parse(const std::array<std::pair<T, std::string_view>, N>& table,
                       std::string_view name) {
  for (const auto& [value, text] : table) {
    if (text == name) return value;
  }
  return std::nullopt;
}

template <class T, std::size_t N>
std::string_view nameOf(const std::array<std::pair<T, std::string_view>, N>& table, T value) {
  for (const auto& [v, text] : table) {
    if (v == value) return text;
  }
  return "?";
}

}  // namespace

std::optional<ColorMode> parseColorMode(std::string_view name) {
  return parse(kColorModes, name);
}
std::optional<PointSizeMode> parsePointSizeMode(std::string_view name) {
  return parse(kSizeModes, name);
}
std::optional<PointShape> parsePointShape(std::string_view name) {
  return parse(kShapes, name);
}
std::string_view colorModeName(ColorMode mode) {
  return nameOf(kColorModes, mode);
}
std::string_view pointSizeModeName(PointSizeMode mode) {
  return nameOf(kSizeModes, mode);
}
std::string_view pointShapeName(PointShape shape) {
  return nameOf(kShapes, shape);
}

std::optional<RasterizerKind> parseRasterizerKind(std::string_view name) {
  return parse(kRasterizers, name);
}
std::string_view rasterizerKindName(RasterizerKind kind) {
  return nameOf(kRasterizers, kind);
}

RenderSettings viewerLook(RenderSettings settings, const RenderSettings& asked,
                          ViewerLookChoice choice, LookTraits traits) {
  if (choice.size) {
    settings.size_mode = traits.spacing_known ? PointSizeMode::Adaptive : asked.size_mode;
    settings.shape = traits.spacing_known ? PointShape::Round : asked.shape;
  }
  if (choice.lighting) settings.lighting = traits.has_normals;
  return settings;
}

AttributeSelection attributesDrawn(const RenderSettings& settings) {
  std::vector<std::string> names;
  if (!settings.scalar.field.empty()) names.push_back(settings.scalar.field);
  // Normals are three extra-bytes columns in LAS: each is asked by its name.
  const auto add_normals = [&] {
    for (const char* axis : {column_names::kNx, column_names::kNy, column_names::kNz})
      names.emplace_back(axis);
  };
  switch (settings.color) {
    case ColorMode::Rgb:
      names.emplace_back(column_names::kRed);
      break;
    case ColorMode::Intensity:
      names.emplace_back(column_names::kIntensity);
      break;
    case ColorMode::Classification:
      names.emplace_back(column_names::kClassification);
      break;
    case ColorMode::Normal:
      add_normals();
      break;
    case ColorMode::Elevation:
    case ColorMode::Uniform:
      break;
  }
  if (settings.lighting && settings.color != ColorMode::Normal) add_normals();
  for (std::string& name : attributesTested(settings.filter)) names.push_back(std::move(name));
  AttributeSelection selection = AttributeSelection::only({});
  for (std::string& name : names) selection.add(std::move(name));  // (no name twice)
  return selection;
}

std::string colorModeNames() {
  // Appended piece by piece: `"|" + std::string(text)` builds a temporary by inserting at its
  // front, which GCC 12 at -O2 misreads as an overlapping memcpy (-Wrestrict, GCC bug 105329).
  std::string names;
  for (const auto& [mode, text] : kColorModes) {
    if (!names.empty()) names += '|';
    names += text;
  }
  return names;
}

}  // namespace parallax
