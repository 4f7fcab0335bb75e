// Names of the ASPRS standard point classes (LAS 1.4 R15, table 17: classes 0-18), the one table
// the viewer's filter panel and classification legend read.
#pragma once

#include <string>
#include <string_view>

namespace parallax {

// "ground" for 2, ...; empty for a class the standard reserves or leaves to users (8, 12, 19+).
std::string_view asprsClassName(int classification);

// asprsClassName, or "class N" where the standard has no name.
std::string classLabel(int classification);

}  // namespace parallax
