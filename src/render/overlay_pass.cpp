#include "render/overlay_pass.h"

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <vector>

#include "render/overlay_geometry.h"

namespace parallax {

namespace {

const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec2 pixel;
layout(location = 1) in float depth_varying;
layout(location = 2) in vec2 test_pixel;
layout(location = 3) in vec2 uv;
layout(location = 4) in vec4 color;
uniform vec2 canvas_size;
noperspective out float v_depth;
noperspective out vec2 v_test;
noperspective out vec2 v_uv;
noperspective out vec4 v_color;
void main() {
  gl_Position = vec4(pixel / canvas_size * 2.0 - 1.0, 0.0, 1.0);
  v_depth = depth_varying;
  v_test = test_pixel;
  v_uv = uv;
  v_color = color;
}
)";

// proj = (P[2][2], P[3][2], P[2][3], P[3][3]) of the view's projection (column-major GLM
// indices): a depth value s of the reversed [0, 1] range is s = (P22 ze + P32) / (P23 ze + P33)
// for eye-space z ze, so ze = (P32 - s P33) / (s P23 - P22) and the eye depth is -ze. The
// off-axis stereo shear changes x only, so it holds for the eyes too.
const char* kFragmentShader = R"(#version 450 core
noperspective in float v_depth;
noperspective in vec2 v_test;
noperspective in vec2 v_uv;
noperspective in vec4 v_color;
uniform sampler2D scene_depth;
uniform sampler2D font;
uniform sampler2D picture;
uniform int image;  // 1: an OverlayImage's triangles, (u, v) over the eye depth in perspective
uniform vec4 proj;
uniform int perspective;
uniform float tolerance;
uniform float absolute_tolerance;
uniform float hidden_alpha;
out vec4 fragment;
void main() {
  float depth = perspective != 0 ? 1.0 / v_depth : v_depth;
  ivec2 at = v_test.x < 0.0 ? ivec2(gl_FragCoord.xy) : ivec2(v_test);
  at = clamp(at, ivec2(0), textureSize(scene_depth, 0) - 1);
  float s = texelFetch(scene_depth, at, 0).r;
  bool hidden = false;
  if (s > 0.0) {  // 0: no point drawn there (reversed depth clears to 0)
    float scene = -(proj.y - s * proj.w) / (s * proj.z - proj.x);
    hidden = scene < depth - tolerance * abs(depth) - absolute_tolerance;
  }
  float alpha = v_color.a * (hidden ? hidden_alpha : 1.0);
  vec3 rgb = v_color.rgb;
  if (image != 0) {
    vec4 texel = texture(picture, perspective != 0 ? v_uv / v_depth : v_uv);
    rgb *= texel.rgb;
    alpha *= texel.a;
  } else if (v_uv.x >= 0.0) {
    alpha *= texture(font, v_uv).r;
  }
  if (alpha <= 0.0) discard;
  fragment = vec4(rgb, alpha);
}
)";

}  // namespace

OverlayPass::OverlayPass()
    : program_({{GL_VERTEX_SHADER, "overlay_pass.vert", kVertexShader},
                {GL_FRAGMENT_SHADER, "overlay_pass.frag", kFragmentShader}}) {
  glCreateVertexArrays(1, &vao_);
  glCreateBuffers(1, &buffer_);
  glVertexArrayVertexBuffer(vao_, 0, buffer_, 0, sizeof(OverlayVertex));
  auto attribute = [&](GLuint index, GLint size, std::size_t offset) {
    glEnableVertexArrayAttrib(vao_, index);
    glVertexArrayAttribFormat(vao_, index, size, GL_FLOAT, GL_FALSE, GLuint(offset));
    glVertexArrayAttribBinding(vao_, index, 0);
  };
  attribute(0, 2, offsetof(OverlayVertex, x));
  attribute(1, 1, offsetof(OverlayVertex, inverse_depth));
  attribute(2, 2, offsetof(OverlayVertex, test_x));
  attribute(3, 2, offsetof(OverlayVertex, u));
  attribute(4, 4, offsetof(OverlayVertex, color));

  glCreateTextures(GL_TEXTURE_2D, 1, &font_texture_);
  glTextureStorage2D(font_texture_, 1, GL_R8, font_.atlasWidth(), font_.atlasHeight());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(font_texture_, 0, 0, 0, font_.atlasWidth(), font_.atlasHeight(), GL_RED,
                      GL_UNSIGNED_BYTE, font_.atlas().data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  // Nearest: the glyphs are placed on whole pixels, one texel each.
  glTextureParameteri(font_texture_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(font_texture_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

OverlayPass::~OverlayPass() {
  for (const PictureTexture& picture : pictures_) glDeleteTextures(1, &picture.texture);
  glDeleteTextures(1, &font_texture_);
  glDeleteBuffers(1, &buffer_);
  glDeleteVertexArrays(1, &vao_);
}

GLuint OverlayPass::pictureTexture(const OverlayImage& image) {
  for (PictureTexture& picture : pictures_) {
    if (picture.pixels == image.rgba) {
      picture.used = true;
      return picture.texture;
    }
  }
  assert(image.width > 0 && image.height > 0 && image.rgba &&
         image.rgba->size() == std::size_t(image.width) * std::size_t(image.height) * 4 &&
         "OverlayImage: rgba must hold width * height RGBA8 pixels");
  PictureTexture picture{image.rgba, 0, true};
  glCreateTextures(GL_TEXTURE_2D, 1, &picture.texture);
  // Mipmapped: a panel seen from afar covers fewer pixels than its picture has.
  int levels = 1;
  for (int size = std::max(image.width, image.height); size > 1; size /= 2) ++levels;
  glTextureStorage2D(picture.texture, levels, GL_RGBA8, image.width, image.height);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTextureSubImage2D(picture.texture, 0, 0, 0, image.width, image.height, GL_RGBA,
                      GL_UNSIGNED_BYTE, image.rgba->data());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glGenerateTextureMipmap(picture.texture);
  glTextureParameteri(picture.texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(picture.texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(picture.texture, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(picture.texture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  pictures_.push_back(picture);
  return picture.texture;
}

void OverlayPass::draw(const OverlayScene& scene, std::span<const View> views,
                       std::span<const ClipRange> ranges, GLuint depth_texture, int canvas_width,
                       int canvas_height, const OverlayDepthSettings& depth) {
  if (scene.empty() || views.empty()) return;
  glUseProgram(program_.id());
  glBindVertexArray(vao_);
  glBindTextureUnit(0, depth_texture);
  glBindTextureUnit(1, font_texture_);
  glUniform1i(program_.uniform("scene_depth"), 0);
  glUniform1i(program_.uniform("font"), 1);
  glUniform1i(program_.uniform("picture"), 2);
  // The pictures' textures: uploaded while their pixels are in the scenes drawn, dropped after
  // the first draw without them.
  for (PictureTexture& picture : pictures_) picture.used = false;
  std::vector<GLuint> picture_textures;
  for (const OverlayImage& image : scene.images) picture_textures.push_back(pictureTexture(image));
  for (PictureTexture& picture : pictures_) {
    if (!picture.used) glDeleteTextures(1, &picture.texture);
  }
  std::erase_if(pictures_, [](const PictureTexture& picture) { return !picture.used; });
  glUniform2f(program_.uniform("canvas_size"), float(canvas_width), float(canvas_height));
  glUniform1f(program_.uniform("tolerance"), float(depth.tolerance));
  glUniform1f(program_.uniform("hidden_alpha"), depth.hidden_alpha);
  glViewport(0, 0, canvas_width, canvas_height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glEnable(GL_SCISSOR_TEST);
  for (std::size_t v = 0; v < views.size() && v < ranges.size(); ++v) {
    const std::vector<OverlayVertex> vertices =
        overlayTriangles(scene, views[v], ranges[v], &font_);
    if (vertices.empty() && scene.images.empty()) continue;
    const Viewport& vp = views[v].viewport;
    // Each eye's overlay stays in its eye's half.
    glScissor(vp.x, vp.y, vp.width, vp.height);
    const glm::dmat4 p = views[v].camera.projectionMatrix(views[v].aspect(), ranges[v]);
    glUniform4f(program_.uniform("proj"), float(p[2][2]), float(p[3][2]), float(p[2][3]),
                float(p[3][3]));
    glUniform1i(program_.uniform("perspective"),
                views[v].camera.projection == Projection::Perspective ? 1 : 0);
    glUniform1f(program_.uniform("absolute_tolerance"),
                float(1e-4 * (ranges[v].far_plane - ranges[v].near_plane)));
    // The pictures first, in the scene's order; the lines, labels and markers over them.
    glUniform1i(program_.uniform("image"), 1);
    for (std::size_t i = 0; i < scene.images.size(); ++i) {
      const std::vector<OverlayVertex> quad =
          overlayImageTriangles(scene.images[i], views[v], ranges[v]);
      if (quad.empty()) continue;
      glBindTextureUnit(2, picture_textures[i]);
      glNamedBufferData(buffer_, GLsizeiptr(quad.size() * sizeof(OverlayVertex)), quad.data(),
                        GL_STREAM_DRAW);
      glDrawArrays(GL_TRIANGLES, 0, GLsizei(quad.size()));
    }
    glUniform1i(program_.uniform("image"), 0);
    if (vertices.empty()) continue;
    glNamedBufferData(buffer_, GLsizeiptr(vertices.size() * sizeof(OverlayVertex)), vertices.data(),
                      GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertices.size()));
  }
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  glBindVertexArray(0);
  glUseProgram(0);
}

}  // namespace parallax
