// A file's bytes seen as text, without a copy: the text formats' readers (text, PTX, PTS, PCD's
// header) parse the mapped file in place.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>

namespace parallax {

inline std::string_view bytesAsText(std::span<const std::byte> bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

}  // namespace parallax
