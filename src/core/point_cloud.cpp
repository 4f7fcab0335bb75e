#include "core/point_cloud.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "core/column_names.h"

namespace parallax {

double ScalarColumn::valueAsDouble(std::size_t i) const {
  switch (type) {
    case ScalarType::Int8:
      return as<std::int8_t>()[i];
    case ScalarType::UInt8:
      return as<std::uint8_t>()[i];
    case ScalarType::Int16:
      return as<std::int16_t>()[i];
    case ScalarType::UInt16:
      return as<std::uint16_t>()[i];
    case ScalarType::Int32:
      return as<std::int32_t>()[i];
    case ScalarType::UInt32:
      return as<std::uint32_t>()[i];
    case ScalarType::Float32:
      return as<float>()[i];
    case ScalarType::Float64:
      return as<double>()[i];
  }
  return 0.0;
}

void ScalarColumn::setFromDouble(std::size_t i, double value) {
  switch (type) {
    case ScalarType::Int8:
      as<std::int8_t>()[i] = roundToInteger<std::int8_t>(value);
      break;
    case ScalarType::UInt8:
      as<std::uint8_t>()[i] = roundToInteger<std::uint8_t>(value);
      break;
    case ScalarType::Int16:
      as<std::int16_t>()[i] = roundToInteger<std::int16_t>(value);
      break;
    case ScalarType::UInt16:
      as<std::uint16_t>()[i] = roundToInteger<std::uint16_t>(value);
      break;
    case ScalarType::Int32:
      as<std::int32_t>()[i] = roundToInteger<std::int32_t>(value);
      break;
    case ScalarType::UInt32:
      as<std::uint32_t>()[i] = roundToInteger<std::uint32_t>(value);
      break;
    case ScalarType::Float32:
      as<float>()[i] = narrowToFloat(value);
      break;
    case ScalarType::Float64:
      as<double>()[i] = value;
      break;
  }
}

std::vector<std::string> PointCloud::attributeNames() const {
  std::vector<std::string> names = {column_names::kX, column_names::kY, column_names::kZ};
  if (hasColors()) {
    names.insert(names.end(), {column_names::kRed, column_names::kGreen, column_names::kBlue});
    if (source.has_alpha) names.push_back(column_names::kAlpha);
  }
  if (hasNormals())
    names.insert(names.end(), {column_names::kNx, column_names::kNy, column_names::kNz});
  if (hasIntensity()) names.push_back(column_names::kIntensity);
  if (hasClassification()) names.push_back(column_names::kClassification);
  for (const auto& column : scalars) names.push_back(column.name);
  return names;
}

namespace {

// The attributes that travel together: a colour channel the source did not name goes beside the
// ones it did.
int groupOf(const std::string& name) {
  if (name == column_names::kX || name == column_names::kY || name == column_names::kZ) return 1;
  if (name == column_names::kRed || name == column_names::kGreen || name == column_names::kBlue ||
      name == column_names::kAlpha) {
    return 2;
  }
  if (name == column_names::kNx || name == column_names::kNy || name == column_names::kNz) return 3;
  return 0;
}

std::string joinNames(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ",") + name;
  return text;
}

}  // namespace

std::vector<std::string> PointCloud::attributeOrder(const std::vector<std::string>& chosen) const {
  const std::vector<std::string> names = attributeNames();
  const auto indexIn = [](const std::vector<std::string>& list, const std::string& name) {
    return std::size_t(std::find(list.begin(), list.end(), name) - list.begin());
  };
  if (!chosen.empty()) {
    for (std::size_t i = 0; i < chosen.size(); ++i) {
      if (indexIn(names, chosen[i]) == names.size()) {
        throw std::invalid_argument("no attribute '" + chosen[i] + "' (there are " +
                                    joinNames(names) + ")");
      }
      if (indexIn(chosen, chosen[i]) != i) {
        throw std::invalid_argument("attribute '" + chosen[i] + "' named twice");
      }
    }
    for (const char* axis : {column_names::kX, column_names::kY, column_names::kZ}) {
      if (indexIn(chosen, axis) == chosen.size()) {
        throw std::invalid_argument(std::string("the attributes must include ") + axis +
                                    " (x, y and z are the point)");
      }
    }
    return chosen;
  }
  // Rank: the source's position; an attribute it does not name goes right after the last of its
  // group it does name, else after everything (both in attributeNames()'s order).
  const std::vector<std::string>& order = source.order;
  std::vector<std::pair<double, std::size_t>> ranked;
  for (std::size_t i = 0; i < names.size(); ++i) {
    double rank = double(order.size() + 1) + double(i) / double(names.size());
    const std::size_t at = indexIn(order, names[i]);
    if (at < order.size()) {
      rank = double(at);
    } else if (const int group = groupOf(names[i]); group != 0) {
      for (std::size_t j = 0; j < order.size(); ++j) {
        if (groupOf(order[j]) == group && indexIn(names, order[j]) < names.size()) {
          rank = double(j) + 0.5 + double(i) / double(4 * names.size());
        }
      }
    }
    ranked.emplace_back(rank, i);
  }
  std::stable_sort(ranked.begin(), ranked.end());
  std::vector<std::string> out;
  for (const auto& [rank, i] : ranked) out.push_back(names[i]);
  return out;
}

const ScalarColumn* PointCloud::findScalar(const std::string& name) const {
  for (const auto& column : scalars) {
    if (column.name == name) return &column;
  }
  return nullptr;
}

void PointCloud::computeBounds() {
  struct IntBox {
    Int3 lo{INT32_MAX, INT32_MAX, INT32_MAX};
    Int3 hi{INT32_MIN, INT32_MIN, INT32_MIN};
  };
  const Int3* p = positions.data();
  IntBox box = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, count, 1 << 16), IntBox{},
      [p](const tbb::blocked_range<std::size_t>& range, IntBox acc) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          acc.lo.x = std::min(acc.lo.x, p[i].x), acc.hi.x = std::max(acc.hi.x, p[i].x);
          acc.lo.y = std::min(acc.lo.y, p[i].y), acc.hi.y = std::max(acc.hi.y, p[i].y);
          acc.lo.z = std::min(acc.lo.z, p[i].z), acc.hi.z = std::max(acc.hi.z, p[i].z);
        }
        return acc;
      },
      [](IntBox a, const IntBox& b) {
        a.lo = {std::min(a.lo.x, b.lo.x), std::min(a.lo.y, b.lo.y), std::min(a.lo.z, b.lo.z)};
        a.hi = {std::max(a.hi.x, b.hi.x), std::max(a.hi.y, b.hi.y), std::max(a.hi.z, b.hi.z)};
        return a;
      });
  bounds = Bounds3{};
  if (count == 0) return;
  bounds.extend(quantization.toWorld(0, box.lo.x), quantization.toWorld(1, box.lo.y),
                quantization.toWorld(2, box.lo.z));
  bounds.extend(quantization.toWorld(0, box.hi.x), quantization.toWorld(1, box.hi.y),
                quantization.toWorld(2, box.hi.z));
}

PointCloud PointCloud::clone() const {
  PointCloud copy;
  copy.count = count;
  copy.quantization = quantization;
  copy.positions = positions.clone();
  copy.colors = colors.clone();
  copy.stored_colors = stored_colors.clone();
  copy.normals = normals.clone();
  copy.intensity = intensity.clone();
  copy.classification = classification.clone();
  for (const auto& column : scalars) {
    copy.scalars.push_back({column.name, column.type, column.data.clone()});
  }
  copy.source = source;
  copy.bounds = bounds;
  return copy;
}

}  // namespace parallax
