// `parallax view INPUT --xr`: the cloud in an OpenXR headset (src/xr), drawn headless through
// EGL with the look options of `view` and `render`. Built where the OpenXR loader was found
// (PARALLAX_XR); elsewhere --xr says so.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "render_options.h"

namespace parallax::cli {

struct XrViewOptions {
  std::string input;
  RenderOptions render;
  LodOptions lod;
  std::vector<double> origin;  // --xr-origin X,Y,Z; empty: the centre of the cloud's base
  double scale = 0.0;          // --xr-scale S; 0: 1 (true scale), or the tabletop preset's
  bool tabletop = false;       // --xr-tabletop: the cloud fits in 1 m
  bool no_mirror = false;      // --xr-no-mirror: draw headless even where a display is
  int mirror_width = 1280, mirror_height = 720;  // view's --width, --height
  ViewerLookChoice look;  // what view's options leave to the viewer (its look defaults)
  bool vignette = false;  // --xr-vignette: narrow the view while flying
  long long frames = 0;   // --xr-frames N: end the session after N frames; 0: the runtime ends it
  // view's --measurements FILE: its measurements are shown (when it exists) and the headset's
  // written back to it when the session ends; empty: nothing is saved.
  std::string measurements_file;
  double profile_width = 1.0;  // view's --profile-width: the corridor of profiles made
};

// Runs the session; 0 when the runtime ended it. Throws XrError (no runtime, no headset: the
// caller prints it and exits 1), InputError or std::invalid_argument.
int runXrView(const XrViewOptions& options);

// False in a build without OpenXR.
bool xrViewAvailable();

// `bench xr` (command_bench_xr.cpp; without OpenXR, xr_view_none.cpp's says so), registered by
// addBenchCommand.
Command addBenchXrCommand(CLI::App& bench);

}  // namespace parallax::cli
