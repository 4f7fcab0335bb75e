// A list of attribute names as the viewer prints it on stderr ("read later from f.laz: a b c").
#pragma once

#include <string>
#include <vector>

namespace parallax::viewer_internal {

inline std::string joinedNames(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) {
    if (!text.empty()) text += ' ';  // (appended: GCC 12's -Wrestrict, bug 105329)
    text += name;
  }
  return text;
}

}  // namespace parallax::viewer_internal
