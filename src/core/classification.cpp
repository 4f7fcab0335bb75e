#include "core/classification.h"

#include <array>

namespace parallax {

namespace {

// LAS 1.4 R15, table 17. 8 (a model key-point in LAS 1.1-1.3) and 12 (overlap points there) are
// reserved in 1.4, where a flag replaced them: they are shown by number.
constexpr std::array<std::string_view, 19> kAsprsClasses{
    "never classified",
    "unclassified",
    "ground",
    "low vegetation",
    "medium vegetation",
    "high vegetation",
    "building",
    "low point (noise)",
    "",
    "water",
    "rail",
    "road surface",
    "",
    "wire guard",
    "wire conductor",
    "transmission tower",
    "wire-structure connector",
    "bridge deck",
    "high noise",
};

}  // namespace

std::string_view asprsClassName(int classification) {
  if (classification < 0 || classification >= int(kAsprsClasses.size())) return {};
  return kAsprsClasses[std::size_t(classification)];
}

std::string classLabel(int classification) {
  const std::string_view name = asprsClassName(classification);
  if (!name.empty()) return std::string(name);
  return "class " + std::to_string(classification);
}

}  // namespace parallax
