#include "core/scalar_type.h"

#include <array>
#include <utility>

namespace parallax {

std::size_t scalarSize(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
    case ScalarType::UInt8:
      return 1;
    case ScalarType::Int16:
    case ScalarType::UInt16:
      return 2;
    case ScalarType::Int32:
    case ScalarType::UInt32:
    case ScalarType::Float32:
      return 4;
    case ScalarType::Float64:
      return 8;
  }
  return 0;
}

std::string_view scalarName(ScalarType type) {
  switch (type) {
    case ScalarType::Int8:
      return "char";
    case ScalarType::UInt8:
      return "uchar";
    case ScalarType::Int16:
      return "short";
    case ScalarType::UInt16:
      return "ushort";
    case ScalarType::Int32:
      return "int";
    case ScalarType::UInt32:
      return "uint";
    case ScalarType::Float32:
      return "float";
    case ScalarType::Float64:
      return "double";
  }
  return "?";
}

std::optional<ScalarType> parseScalarType(std::string_view name) {
  static constexpr std::array<std::pair<std::string_view, ScalarType>, 16> kNames = {{
      {"char", ScalarType::Int8},
      {"int8", ScalarType::Int8},
      {"uchar", ScalarType::UInt8},
      {"uint8", ScalarType::UInt8},
      {"short", ScalarType::Int16},
      {"int16", ScalarType::Int16},
      {"ushort", ScalarType::UInt16},
      {"uint16", ScalarType::UInt16},
      {"int", ScalarType::Int32},
      {"int32", ScalarType::Int32},
      {"uint", ScalarType::UInt32},
      {"uint32", ScalarType::UInt32},
      {"float", ScalarType::Float32},
      {"float32", ScalarType::Float32},
      {"double", ScalarType::Float64},
      {"float64", ScalarType::Float64},
  }};
  for (const auto& [text, type] : kNames) {
    if (text == name) return type;
  }
  return std::nullopt;
}

}  // namespace parallax
