// `view --xr` in a build without the OpenXR loader (PARALLAX_XR off).
#include <stdexcept>

#include "xr_view.h"

namespace parallax::cli {

bool xrViewAvailable() {
  return false;
}

int runXrView(const XrViewOptions&) {
  throw std::runtime_error(
      "--xr: this parallax was built without OpenXR (install libopenxr-dev and rebuild with "
      "-DPARALLAX_XR=ON)");
}

}  // namespace parallax::cli
