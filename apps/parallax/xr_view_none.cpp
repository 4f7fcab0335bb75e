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

Command addBenchXrCommand(CLI::App& bench) {
  Command command;
  command.subcommand =
      bench.add_subcommand("xr", "A headset frame of view --xr; not in this build");
  command.run = []() -> int {
    throw std::runtime_error("bench xr: this parallax was built without OpenXR");
  };
  return command;
}

}  // namespace parallax::cli
