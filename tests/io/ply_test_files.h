// Building PLY files inside tests (header text and body values, packed as the format wants them)
// and reading them back into plain vectors for exact comparisons.
//
// The builders never call the reader under test (parseScalarType from core is their only
// library call), so that a bug in the reader cannot hide in the helper that builds its input;
// the read-back helpers use only the reader's public API.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <charconv>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/point_cloud.h"
#include "core/scalar_type.h"
#include "io/ply_header.h"
#include "io/ply_reader.h"
#include "support/file_bytes.h"

namespace parallax::test {

inline constexpr PlyFormat kAllPlyFormats[] = {PlyFormat::Ascii, PlyFormat::BinaryLittleEndian,
                                               PlyFormat::BinaryBigEndian};

// The format keyword as the PLY specification spells it.
inline std::string formatKeyword(PlyFormat format) {
  switch (format) {
    case PlyFormat::Ascii:
      return "ascii";
    case PlyFormat::BinaryLittleEndian:
      return "binary_little_endian";
    case PlyFormat::BinaryBigEndian:
      return "binary_big_endian";
  }
  return "?";
}

// "ply", "format <format> 1.0", then `lines`, then "end_header", each ended by `eol`.
inline std::string plyHeader(PlyFormat format, std::initializer_list<std::string_view> lines,
                             std::string_view eol = "\n") {
  std::string text = "ply";
  text += eol;
  text += "format " + formatKeyword(format) + " 1.0";
  text += eol;
  for (std::string_view line : lines) {
    text += line;
    text += eol;
  }
  text += "end_header";
  text += eol;
  return text;
}

// Appends body values in a format: binary values packed in its byte order, ascii values as
// shortest round-trip text separated by one space, one record per line.
class PlyBody {
 public:
  explicit PlyBody(PlyFormat format) : format_(format) {}

  // `T` is one of the eight PLY scalar types.
  template <class T>
  PlyBody& put(T value) {
    static_assert(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>);
    if (format_ == PlyFormat::Ascii) {
      if (!at_line_start_) bytes_ += ' ';
      at_line_start_ = false;
      char text[64];
      std::to_chars_result result;
      if constexpr (std::is_integral_v<T> && sizeof(T) == 1) {
        result = std::to_chars(text, text + sizeof text, int(value));
      } else {
        result = std::to_chars(text, text + sizeof text, value);
      }
      bytes_.append(text, result.ptr);
      return *this;
    }
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    bool file_big = format_ == PlyFormat::BinaryBigEndian;
    bool host_big = std::endian::native == std::endian::big;
    if (file_big != host_big) {
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    }
    bytes_.append(reinterpret_cast<const char*>(raw), sizeof(T));
    return *this;
  }

  // A value of a type chosen at run time (converted from double, which holds every test value).
  PlyBody& put(ScalarType type, double value) {
    switch (type) {
      case ScalarType::Int8:
        return put(std::int8_t(value));
      case ScalarType::UInt8:
        return put(std::uint8_t(value));
      case ScalarType::Int16:
        return put(std::int16_t(value));
      case ScalarType::UInt16:
        return put(std::uint16_t(value));
      case ScalarType::Int32:
        return put(std::int32_t(value));
      case ScalarType::UInt32:
        return put(std::uint32_t(value));
      case ScalarType::Float32:
        return put(float(value));
      case ScalarType::Float64:
        return put(value);
    }
    return *this;
  }

  // Ends a record: a line end in ascii, nothing in binary.
  PlyBody& end(std::string_view eol = "\n") {
    if (format_ == PlyFormat::Ascii) bytes_ += eol;
    at_line_start_ = true;
    return *this;
  }

  // Raw text or bytes, unchanged.
  PlyBody& raw(std::string_view bytes) {
    bytes_ += bytes;
    return *this;
  }

  const std::string& bytes() const { return bytes_; }

 private:
  PlyFormat format_;
  std::string bytes_;
  bool at_line_start_ = true;
};

// What a call threw. `thrown` is false (and a failure is recorded) when it threw no InputError.
struct CaughtInputError {
  bool thrown = false;
  std::string message;
  InputErrorInfo info;
};

template <class F>
CaughtInputError catchInputError(F&& call) {
  CaughtInputError caught;
  try {
    call();
    ADD_FAILURE() << "expected an InputError, but nothing was thrown";
  } catch (const InputError& error) {
    caught.thrown = true;
    caught.message = error.what();
    caught.info = error.info();
  } catch (const std::exception& error) {
    ADD_FAILURE() << "expected an InputError, got another exception: " << error.what();
  }
  return caught;
}

// Every part must appear in the message.
inline void expectMessageHas(const CaughtInputError& caught,
                             std::initializer_list<std::string_view> parts) {
  ASSERT_TRUE(caught.thrown);
  for (std::string_view part : parts) {
    EXPECT_NE(caught.message.find(part), std::string::npos)
        << "message lacks \"" << part << "\": " << caught.message;
  }
}

// An error that says both what it wanted and what it got.
inline void expectExpectedAndFound(const CaughtInputError& caught) {
  ASSERT_TRUE(caught.thrown);
  EXPECT_FALSE(caught.info.expected.empty()) << caught.message;
  EXPECT_FALSE(caught.info.found.empty()) << caught.message;
}

inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// ---------------------------------------------------------------------------------------------
// Reading back: world coordinates and columns as plain vectors, for exact comparisons.

using World = std::array<double, 3>;

inline PointCloud readPlyText(const std::string& bytes, bool parallel = true) {
  PlyReadOptions options;
  options.parallel = parallel;
  return readPlyFromMemory(asBytes(bytes), "test.ply", options);
}

inline std::vector<World> worldPositions(const PointCloud& cloud) {
  std::vector<World> out;
  for (std::size_t i = 0; i < cloud.positions.size(); ++i) {
    out.push_back({cloud.worldX(i), cloud.worldY(i), cloud.worldZ(i)});
  }
  return out;
}

inline std::vector<Rgba8> colors(const PointCloud& cloud) {
  return {cloud.colors.begin(), cloud.colors.end()};
}

inline std::vector<Float3> normals(const PointCloud& cloud) {
  return {cloud.normals.begin(), cloud.normals.end()};
}

// The values of a scalar column, after checking its type and size.
template <class T>
std::vector<T> scalarValues(const PointCloud& cloud, const std::string& name, ScalarType type) {
  const ScalarColumn* column = cloud.findScalar(name);
  if (column == nullptr) {
    ADD_FAILURE() << "no scalar column '" << name << "'";
    return {};
  }
  EXPECT_EQ(column->type, type) << name;
  if (column->type != type || column->data.size() != cloud.count * sizeof(T)) {
    ADD_FAILURE() << name << ": " << column->data.size() << " bytes for " << cloud.count
                  << " points";
    return {};
  }
  return {column->as<T>(), column->as<T>() + cloud.count};
}

inline std::vector<std::string> scalarNames(const PointCloud& cloud) {
  std::vector<std::string> names;
  for (const ScalarColumn& column : cloud.scalars) names.push_back(column.name);
  return names;
}

// Every column of `a` equals that of `b`, positions compared in world coordinates.
inline void expectSamePoints(const PointCloud& a, const PointCloud& b) {
  ASSERT_EQ(a.count, b.count);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.count; ++i) {
    ASSERT_EQ(a.worldX(i), b.worldX(i)) << "point " << i;
    ASSERT_EQ(a.worldY(i), b.worldY(i)) << "point " << i;
    ASSERT_EQ(a.worldZ(i), b.worldZ(i)) << "point " << i;
  }
  EXPECT_EQ(colors(a), colors(b));
  EXPECT_EQ(normals(a), normals(b));
  EXPECT_EQ(std::vector<float>(a.intensity.begin(), a.intensity.end()),
            std::vector<float>(b.intensity.begin(), b.intensity.end()));
  EXPECT_EQ(std::vector<std::uint8_t>(a.classification.begin(), a.classification.end()),
            std::vector<std::uint8_t>(b.classification.begin(), b.classification.end()));
  ASSERT_EQ(scalarNames(a), scalarNames(b));
  for (std::size_t s = 0; s < a.scalars.size(); ++s) {
    EXPECT_EQ(a.scalars[s].type, b.scalars[s].type);
    ASSERT_EQ(a.scalars[s].data.size(), b.scalars[s].data.size());
    EXPECT_EQ(0, std::memcmp(a.scalars[s].data.data(), b.scalars[s].data.data(),
                             a.scalars[s].data.size()))
        << a.scalars[s].name;
  }
}

// A vertex element of x, y, z of one type (a PLY type name) holding `points`.
inline std::string positionFile(PlyFormat format, const std::string& type,
                                const std::vector<World>& points) {
  std::string header = plyHeader(format, {});
  std::string lines = "element vertex " + std::to_string(points.size()) + "\nproperty " + type +
                      " x\nproperty " + type + " y\nproperty " + type + " z\n";
  header.insert(header.find("end_header"), lines);
  PlyBody body(format);
  ScalarType scalar = *parseScalarType(type);
  for (const World& p : points) body.put(scalar, p[0]).put(scalar, p[1]).put(scalar, p[2]).end();
  return header + body.bytes();
}

// Compares element by element and reports only the first difference (large inputs).
template <class T>
void expectFirstMismatch(const std::vector<T>& actual, const std::vector<T>& expected,
                         const std::string& what) {
  ASSERT_EQ(actual.size(), expected.size()) << what;
  for (std::size_t i = 0; i < actual.size(); ++i) {
    if (!(actual[i] == expected[i])) {
      ADD_FAILURE() << what << ": first difference at index " << i << ": got "
                    << ::testing::PrintToString(actual[i]) << ", expected "
                    << ::testing::PrintToString(expected[i]);
      return;
    }
  }
}

template <class T>
void expectScalarValues(const PointCloud& cloud, const std::string& name, ScalarType type,
                        const std::vector<T>& expected) {
  expectFirstMismatch(scalarValues<T>(cloud, name, type), expected, name);
}

}  // namespace parallax::test
