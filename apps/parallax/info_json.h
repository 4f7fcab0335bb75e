// JSON helpers of `parallax info --json` (command_info.cpp, command_info_copc.cpp): numbers that
// JSON cannot hold (NaN, infinities of an empty cloud's bounds) written as null.
#pragma once

#include <array>
#include <cmath>
#include <nlohmann/json.hpp>

namespace parallax::cli {

using InfoJson = nlohmann::ordered_json;

inline InfoJson finiteOrNull(double v) {
  return std::isfinite(v) ? InfoJson(v) : InfoJson(nullptr);
}

inline InfoJson jsonTriple(const std::array<double, 3>& v) {
  return InfoJson::array({finiteOrNull(v[0]), finiteOrNull(v[1]), finiteOrNull(v[2])});
}

}  // namespace parallax::cli
