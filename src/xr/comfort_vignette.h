// The comfort vignette (issue 24, item 4): while the user flies, each eye's picture fades to
// black outside a cone around its forward direction. Moving through the world while standing
// still is what makes people sick in VR, and it is the periphery's optic flow that does it;
// hiding it while flying, and only then, is the usual remedy (optional: --xr-vignette).
#pragma once

#include <epoxy/gl.h>

#include "render/shader_program.h"
#include "render/view.h"
#include "xr/stage_mapping.h"

namespace parallax {

struct VignetteShape {
  // Tangents of the angle from the eye's forward direction: clear inside `inner`, black beyond
  // `outer`, a smooth ramp between (about 27 and 39 degrees).
  double inner = 0.5, outer = 0.8;
};

class ComfortVignette {
 public:
  ComfortVignette();  // compiles its program; needs a current context for its whole life
  ~ComfortVignette();
  ComfortVignette(const ComfortVignette&) = delete;
  ComfortVignette& operator=(const ComfortVignette&) = delete;

  // Darkens `viewport` of `framebuffer`, an eye's picture with field of view `fov` (its forward
  // direction, where tan x = tan y = 0, need not be the picture's centre). Leaves blending off.
  void draw(GLuint framebuffer, const Viewport& viewport, const EyeFov& fov,
            const VignetteShape& shape = {});

 private:
  ShaderProgram program_;
  GLuint vao_ = 0;
};

}  // namespace parallax
