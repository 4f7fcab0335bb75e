// The point data model: one column per attribute, positions quantized to int32.
//
// A PointCloud is a whole cloud or one chunk of a stream; both have the same shape. Optional
// attributes are empty columns when absent (check `hasColors()` etc., not the schema). Every
// non-empty column has exactly `count` elements.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/bounds.h"
#include "core/column.h"
#include "core/quantization.h"
#include "core/scalar_type.h"

namespace parallax {

struct Int3 {
  std::int32_t x, y, z;
  friend bool operator==(const Int3&, const Int3&) = default;
};
struct Float3 {
  float x, y, z;
  friend bool operator==(const Float3&, const Float3&) = default;
};
// 8-bit colour; alpha is 255 when the source has none.
struct Rgba8 {
  std::uint8_t r, g, b, a;
  friend bool operator==(const Rgba8&, const Rgba8&) = default;
};

// A colour as a source with 16-bit channels stored it (LAS's Red, Green, Blue), whatever its range.
struct Rgb16 {
  std::uint16_t r, g, b;
  friend bool operator==(const Rgb16&, const Rgb16&) = default;
};

// A property the model has no dedicated column for, kept under its source name and type so that
// writers give it back unchanged. `data` holds count * scalarSize(type) bytes, native endian.
struct ScalarColumn {
  std::string name;
  ScalarType type = ScalarType::Float32;
  ByteBuffer data;

  template <class T>
  const T* as() const {
    return reinterpret_cast<const T*>(data.data());
  }
  template <class T>
  T* as() {
    return reinterpret_cast<T*>(data.data());
  }
  // Value of point i converted to double (for statistics and display).
  double valueAsDouble(std::size_t i) const;
  // Stores `value` as point i in the column's type: integers rounded half away from zero and
  // clamped to the type's range (NaN gives its minimum), float narrowed as IEEE does it.
  void setFromDouble(std::size_t i, double value);
};

// How the source stored the attributes the model normalises (positions to int32, colours to
// 8 bits, normals to float), so a writer can give a file back in its own types.
struct SourceTypes {
  ScalarType position = ScalarType::Float32;
  ScalarType color = ScalarType::UInt8;
  ScalarType normal = ScalarType::Float32;
  ScalarType intensity = ScalarType::Float32;
  // > 0: the format defines its intensity on 0..intensity_full_scale (PTX: 0..1), which writers
  // of 16-bit integer intensity (LAS, LAZ) map onto 0..65535; 0: the values are on that scale
  // already (or the format says nothing), and are written rounded.
  double intensity_full_scale = 0.0;
  ScalarType classification = ScalarType::UInt8;
  bool has_alpha = false;
  // The attributes in the order the source holds them, under attributeNames()'s names (a PLY of
  // x y z nx ny nz red green blue: exactly that), so that writers give the file back in its own
  // order. Empty when the source has no order of its own to keep (LAS, generated clouds).
  std::vector<std::string> order;
};

struct PointCloud {
  std::uint64_t count = 0;
  Quantization quantization;
  Column<Int3> positions;  // always count elements
  Column<Rgba8> colors;    // empty: no colour
  // The colours exactly as a 16-bit source stored them (LAS: 8-bit values in the 16-bit fields
  // stay 8-bit values, 16-bit ones stay 16-bit), so that a LAS or LAZ writer gives them back
  // unchanged; empty when the source stored none or stored 8 bits (PLY uchar). When present,
  // `colors` is their display form (las_reader.h's 8-bit rule), which every other consumer
  // (renderer, PLY, text, E57, PCD writers) reads. Code that changes `colors` clears this
  // column, or the old values would be written back.
  Column<Rgb16> stored_colors;
  Column<Float3> normals;               // empty: no normals
  Column<float> intensity;              // empty: no intensity
  Column<std::uint8_t> classification;  // empty: no classification
  std::vector<ScalarColumn> scalars;    // every other scalar property, in source order
  SourceTypes source;
  // Bounds of the points held, in world coordinates (exact: computed from the quantized values).
  Bounds3 bounds;

  bool hasColors() const { return !colors.empty(); }
  bool hasStoredColors() const { return !stored_colors.empty(); }
  bool hasNormals() const { return !normals.empty(); }
  bool hasIntensity() const { return !intensity.empty(); }
  bool hasClassification() const { return !classification.empty(); }

  double worldX(std::size_t i) const { return quantization.toWorld(0, positions[i].x); }
  double worldY(std::size_t i) const { return quantization.toWorld(1, positions[i].y); }
  double worldZ(std::size_t i) const { return quantization.toWorld(2, positions[i].z); }

  // "x y z", then "red green blue [alpha]", "nx ny nz", "intensity", "classification", then the
  // scalar columns' names: the attributes a user sees in `info`.
  std::vector<std::string> attributeNames() const;

  // attributeNames() in the order a writer puts them: `chosen` when given (a subset of
  // attributeNames() holding x, y and z, in the order wanted), else the source's order
  // (source.order; attributes it does not name follow their group, or go last). Throws
  // std::invalid_argument naming an unknown or repeated name, or a missing x, y or z, with the
  // names there are.
  std::vector<std::string> attributeOrder(const std::vector<std::string>& chosen = {}) const;

  const ScalarColumn* findScalar(const std::string& name) const;

  // Recomputes `bounds` from the positions (parallel).
  void computeBounds();

  // A deep copy (tests, small chunks).
  PointCloud clone() const;
};

}  // namespace parallax
