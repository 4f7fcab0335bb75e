// Building PLY files inside tests: header text and body values, packed as the format wants them.
//
// Written independently of the reader under test (no call into src/io), so that a bug in the
// reader cannot hide in the helper that builds its input.
#pragma once

#include <gtest/gtest.h>

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
#include <vector>

#include "core/error.h"
#include "core/scalar_type.h"
#include "io/ply_header.h"

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

inline std::span<const std::byte> asBytes(const std::string& text) {
  return {reinterpret_cast<const std::byte*>(text.data()), text.size()};
}

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

}  // namespace parallax::test
