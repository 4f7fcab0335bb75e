#include "io/ply_property_map.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

#include "core/column_names.h"
#include "core/error.h"

namespace parallax::ply {
namespace {

std::string lowercase(std::string_view text) {
  std::string out(text);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Names real exporters use (CloudCompare, Meshlab, Agisoft, RealityCapture, COLMAP, PDAL, Open3D).
Target targetForName(const std::string& name) {
  struct Alias {
    const char* name;
    Target target;
  };
  static constexpr Alias kAliases[] = {
      {"x", Target::X},
      {"y", Target::Y},
      {"z", Target::Z},
      {"red", Target::Red},
      {"green", Target::Green},
      {"blue", Target::Blue},
      {"alpha", Target::Alpha},
      {"r", Target::Red},
      {"g", Target::Green},
      {"b", Target::Blue},
      {"a", Target::Alpha},
      {"diffuse_red", Target::Red},
      {"diffuse_green", Target::Green},
      {"diffuse_blue", Target::Blue},
      {"diffuse_alpha", Target::Alpha},
      {"nx", Target::NormalX},
      {"ny", Target::NormalY},
      {"nz", Target::NormalZ},
      {"normal_x", Target::NormalX},
      {"normal_y", Target::NormalY},
      {"normal_z", Target::NormalZ},
      {"intensity", Target::Intensity},
      {"scalar_intensity", Target::Intensity},
      {"classification", Target::Classification},
      {"scalar_classification", Target::Classification},
  };
  for (const auto& alias : kAliases) {
    if (name == alias.name) return alias.target;
  }
  return Target::Scalar;
}

}  // namespace

PointLayout planPointLayout(const PlyElement& element, const std::string& file) {
  PointLayout layout;
  layout.element_name = element.name;
  bool seen[int(Target::Skip) + 1] = {};
  std::size_t offset = 0;
  for (std::size_t i = 0; i < element.properties.size(); ++i) {
    const PlyProperty& property = element.properties[i];
    PropertyPlan plan;
    plan.type = property.type;
    plan.is_list = property.is_list;
    plan.list_count_type = property.list_count_type;
    plan.byte_offset = offset;
    plan.name = property.name;
    if (property.is_list) {
      plan.target = Target::Skip;
      layout.fixed_size = false;
      layout.min_record_size += scalarSize(property.list_count_type);
    } else {
      Target target = targetForName(lowercase(property.name));
      // A second property for the same column (e.g. both "red" and "r") is kept as its own.
      if (target != Target::Scalar && seen[int(target)]) target = Target::Scalar;
      seen[int(target)] = true;
      plan.target = target;
      offset += scalarSize(property.type);
      layout.min_record_size += scalarSize(property.type);
      if (target == Target::Scalar) {
        plan.scalar_index = int(layout.scalars.size());
        layout.scalars.emplace_back(property.name, property.type);
      }
    }
    if (plan.target == Target::X || plan.target == Target::Y || plan.target == Target::Z) {
      layout.position_index[int(plan.target) - int(Target::X)] = int(i);
    }
    layout.properties.push_back(std::move(plan));
  }
  layout.record_size = offset;
  for (int axis = 0; axis < 3; ++axis) {
    if (layout.position_index[axis] < 0) {
      const char* names[] = {"x", "y", "z"};
      std::string found;
      for (const auto& property : element.properties) {
        found += (found.empty() ? "" : " ") + property.name;
      }
      throw InputError({.file = file,
                        .line = element.header_line,
                        .element = element.name,
                        .property = names[axis],
                        .expected = "scalar properties x, y and z",
                        .found = found.empty() ? "no properties" : "properties " + found});
    }
  }
  const auto typeOf = [&](Target target) {
    for (const auto& plan : layout.properties) {
      if (plan.target == target) return plan.type;
    }
    return ScalarType::UInt8;
  };
  layout.source.position = typeOf(Target::X);
  layout.has_color = seen[int(Target::Red)] || seen[int(Target::Green)] || seen[int(Target::Blue)];
  layout.has_alpha = seen[int(Target::Alpha)];
  if (layout.has_alpha) layout.has_color = true;
  if (layout.has_color)
    layout.source.color = typeOf(seen[int(Target::Red)]     ? Target::Red
                                 : seen[int(Target::Green)] ? Target::Green
                                 : seen[int(Target::Blue)]  ? Target::Blue
                                                            : Target::Alpha);
  layout.source.has_alpha = layout.has_alpha;
  layout.has_normals =
      seen[int(Target::NormalX)] || seen[int(Target::NormalY)] || seen[int(Target::NormalZ)];
  if (layout.has_normals) {
    layout.source.normal = typeOf(seen[int(Target::NormalX)]   ? Target::NormalX
                                  : seen[int(Target::NormalY)] ? Target::NormalY
                                                               : Target::NormalZ);
  }
  layout.has_intensity = seen[int(Target::Intensity)];
  if (layout.has_intensity) layout.source.intensity = typeOf(Target::Intensity);
  layout.has_classification = seen[int(Target::Classification)];
  if (layout.has_classification) layout.source.classification = typeOf(Target::Classification);
  // The file's order, under the model's names (what a writer gives back).
  static const char* const kModelNames[] = {
      column_names::kX,     column_names::kY,         column_names::kZ,
      column_names::kRed,   column_names::kGreen,     column_names::kBlue,
      column_names::kAlpha, column_names::kNx,        column_names::kNy,
      column_names::kNz,    column_names::kIntensity, column_names::kClassification};
  for (const auto& plan : layout.properties) {
    if (plan.target == Target::Skip) continue;
    layout.source.order.push_back(plan.target == Target::Scalar ? plan.name
                                                                : kModelNames[int(plan.target)]);
  }
  return layout;
}

PointLayout skippingLayout(const PlyElement& element) {
  PointLayout layout;
  layout.element_name = element.name;
  for (const auto& property : element.properties) {
    PropertyPlan plan;
    plan.target = Target::Skip;
    plan.type = property.type;
    plan.is_list = property.is_list;
    plan.list_count_type = property.list_count_type;
    plan.name = property.name;
    layout.properties.push_back(std::move(plan));
  }
  layout.fixed_size = !element.hasLists();
  layout.record_size = element.fixedRecordSize();
  layout.min_record_size = element.minimumRecordSize();
  return layout;
}

namespace {

bool layoutHasTarget(const PointLayout& layout, Target target) {
  return std::any_of(layout.properties.begin(), layout.properties.end(),
                     [target](const PropertyPlan& p) { return p.target == target; });
}

}  // namespace

void fillMissingChannels(const PointLayout& layout, PointCloud& cloud, std::uint64_t first,
                         std::size_t n) {
  if (n == 0) return;
  if (layout.has_color) {
    constexpr Target kChannels[4] = {Target::Red, Target::Green, Target::Blue, Target::Alpha};
    for (int c = 0; c < 4; ++c) {
      if (layoutHasTarget(layout, kChannels[c])) continue;
      const std::uint8_t value = c == 3 ? 255 : 0;
      std::uint8_t* dst = &cloud.colors[first].r + c;
      for (std::size_t i = 0; i < n; ++i) dst[i * 4] = value;
    }
  }
  if (layout.has_normals) {
    constexpr Target kAxes[3] = {Target::NormalX, Target::NormalY, Target::NormalZ};
    for (int c = 0; c < 3; ++c) {
      if (layoutHasTarget(layout, kAxes[c])) continue;
      float* dst = &cloud.normals[first].x + c;
      for (std::size_t i = 0; i < n; ++i) dst[i * 3] = 0.0f;
    }
  }
}

PointCloud allocatePointCloud(const PointLayout& layout, std::uint64_t count,
                              const Quantization& quantization, ChannelDefaults defaults) {
  PointCloud cloud;
  cloud.count = count;
  cloud.quantization = quantization;
  cloud.source = layout.source;
  cloud.positions = Column<Int3>(count);
  if (layout.has_color) cloud.colors = Column<Rgba8>(count);
  if (layout.has_normals) cloud.normals = Column<Float3>(count);
  if (defaults == ChannelDefaults::FilledAtAllocation && count > 0) {
    fillMissingChannels(layout, cloud, 0, std::size_t(count));
  }
  if (layout.has_intensity) cloud.intensity = Column<float>(count);
  if (layout.has_classification) cloud.classification = Column<std::uint8_t>(count);
  for (const auto& [name, type] : layout.scalars) {
    cloud.scalars.push_back({name, type, ByteBuffer(count * scalarSize(type))});
  }
  return cloud;
}

}  // namespace parallax::ply
