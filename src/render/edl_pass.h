// Eye-dome lighting (Boucheny, "Interactive scientific visualization of large datasets", 2009):
// a screen-space post pass that darkens each pixel by how much nearer its neighbours are, in log
// depth, which outlines shapes in clouds that have no normals. Needs no normals and no lights.
#pragma once

#include <epoxy/gl.h>

#include "render/render_settings.h"
#include "render/shader_program.h"
#include "render/view.h"

namespace parallax {

class EdlPass {
 public:
  EdlPass();  // needs a current 4.5 context
  ~EdlPass();
  EdlPass(const EdlPass&) = delete;
  EdlPass& operator=(const EdlPass&) = delete;

  // Reads `color` (RGBA8) and `eye_depth` (RG32F: linear eye depth times coverage, coverage; 0
  // where no point was drawn) and
  // writes the shaded picture into the bound framebuffer inside `viewport` (same pixel grid as the
  // textures). Depth test and blending are off while it runs.
  void draw(GLuint color, GLuint eye_depth, const Viewport& viewport,
            const RenderSettings& settings);

 private:
  ShaderProgram program_;
  GLuint vao_ = 0;  // empty: the full-screen triangle comes from gl_VertexID
};

}  // namespace parallax
