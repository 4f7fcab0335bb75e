// Scalar types of point attributes, named as PLY names them (the richest of our formats).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace parallax {

enum class ScalarType : std::uint8_t {
  Int8,
  UInt8,
  Int16,
  UInt16,
  Int32,
  UInt32,
  Float32,
  Float64
};

// Size of one value in bytes: 1, 2, 4 or 8.
std::size_t scalarSize(ScalarType type);

// PLY's canonical name: char uchar short ushort int uint float double.
std::string_view scalarName(ScalarType type);

// Accepts the canonical names and the sized aliases (int8 uint8 int16 uint16 int32 uint32 float32
// float64); nullopt for anything else.
std::optional<ScalarType> parseScalarType(std::string_view name);

constexpr bool isFloatingPoint(ScalarType type) {
  return type == ScalarType::Float32 || type == ScalarType::Float64;
}

}  // namespace parallax
