// The overlay pass: the triangles of render/overlay_geometry.h (pictures on quads, lines,
// markers, labels) blended over a finished picture, each view in its viewport with its own
// camera (each eye in stereo), depth-tested against the points of the frame.
//
// Depth: the pass reads the frame's depth texture (reversed, [0, 1]), turns it into linear eye
// depth with the view's projection, and compares it with the overlay fragment's eye depth. An
// overlay fragment more than `tolerance` (relative) behind the points at its pixel (a marker or
// label: at its anchor's pixel) is drawn faded, at `hidden_alpha` of its opacity, rather than
// not at all: a measurement behind a wall stays findable, and reads as behind. A pixel with no
// point hides nothing.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "render/overlay.h"
#include "render/overlay_font.h"
#include "render/shader_program.h"
#include "render/view.h"

namespace parallax {

struct OverlayDepthSettings {
  // Relative eye-depth tolerance: a measurement's vertices are points of the cloud, drawn as
  // splats at their own depth; the line between two of them runs along the surface, whose other
  // points may be a little nearer (noise, splat size).
  double tolerance = 0.01;
  float hidden_alpha = 0.3f;
};

class OverlayPass {
 public:
  OverlayPass();  // compiles the program and uploads the font atlas; needs a current context
  ~OverlayPass();
  OverlayPass(const OverlayPass&) = delete;
  OverlayPass& operator=(const OverlayPass&) = delete;

  // Draws `scene` into the bound draw framebuffer of canvas_width x canvas_height pixels, for
  // each view (viewports in that framebuffer's pixels, ranges as the points were drawn with),
  // depth-tested against `depth_texture` (the same size, the points' reversed depth). Leaves
  // blending and the scissor test off and the viewport at the whole canvas.
  void draw(const OverlayScene& scene, std::span<const View> views,
            std::span<const ClipRange> ranges, GLuint depth_texture, int canvas_width,
            int canvas_height, const OverlayDepthSettings& depth = {});

  const OverlayFont& font() const { return font_; }

 private:
  // An OverlayImage's texture, kept while its pixels (the same shared block) are in the scenes.
  struct PictureTexture {
    std::shared_ptr<const std::vector<std::uint8_t>> pixels;  // held: its address stays unique
    GLuint texture = 0;
    bool used = false;
  };
  GLuint pictureTexture(const OverlayImage& image);

  OverlayFont font_;
  std::vector<PictureTexture> pictures_;
  ShaderProgram program_;
  GLuint vao_ = 0, buffer_ = 0, font_texture_ = 0;
};

}  // namespace parallax
