#include "render/renderer.h"

#include <cassert>
#include <cstring>
#include <stdexcept>

namespace parallax {

namespace {

GLuint makeTexture(GLenum format, int width, int height) {
  GLuint texture = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &texture);
  glTextureStorage2D(texture, 1, format, width, height);
  glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return texture;
}

void checkComplete(GLuint framebuffer, const char* what) {
  const GLenum status = glCheckNamedFramebufferStatus(framebuffer, GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error(std::string(what) + " framebuffer incomplete (status 0x" +
                             std::to_string(status) + ")");
  }
}

}  // namespace

Renderer::Renderer() = default;

Renderer::~Renderer() { resize(0, 0); }

void Renderer::resize(int width, int height) {
  if (width == width_ && height == height_) return;
  if (framebuffer_) {
    glDeleteFramebuffers(1, &framebuffer_);
    const GLuint textures[] = {color_, eye_depth_, depth_};
    glDeleteTextures(3, textures);
    framebuffer_ = color_ = eye_depth_ = depth_ = 0;
  }
  width_ = width, height_ = height;
  if (width <= 0 || height <= 0) return;
  color_ = makeTexture(GL_RGBA8, width, height);
  eye_depth_ = makeTexture(GL_R32F, width, height);
  depth_ = makeTexture(GL_DEPTH_COMPONENT32F, width, height);
  glCreateFramebuffers(1, &framebuffer_);
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, color_, 0);
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT1, eye_depth_, 0);
  glNamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, depth_, 0);
  checkComplete(framebuffer_, "the renderer's");
}

FrameStats Renderer::render(const GpuPointCloud& cloud, std::span<const View> views,
                            const RenderSettings& settings, GLuint target, int width, int height) {
  resize(width, height);
  FrameStats stats;
  if (width <= 0 || height <= 0) return stats;

  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glDisable(GL_SCISSOR_TEST);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(framebuffer_, 2, both);
  const float background[] = {settings.background[0], settings.background[1],
                              settings.background[2], 1.0f};
  const float zero[] = {0.0f, 0.0f, 0.0f, 0.0f};
  const float far_depth = 0.0f;  // reversed depth: 0 is infinitely far
  glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 0, background);
  glClearNamedFramebufferfv(framebuffer_, GL_COLOR, 1, zero);
  glClearNamedFramebufferfv(framebuffer_, GL_DEPTH, 0, &far_depth);
  // Writing eye depth costs a store per fragment: only when a pass or a pick will read it.
  // Picking then falls back to the depth buffer.
  glNamedFramebufferDrawBuffers(framebuffer_, settings.edl ? 2 : 1, both);

  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  last_views_.clear();
  for (const View& view : views) {
    const ClipRange range = view.camera.clipRange(cloud.bounds());
    const PointPassStats pass = point_pass_.draw(cloud, view, range, settings, settings.edl);
    stats.points_drawn += pass.points_drawn;
    stats.chunks_drawn += pass.chunks_drawn;
    stats.chunks_culled += pass.chunks_culled;
    last_views_.push_back({view, range});
  }
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);

  if (settings.edl) {
    glBindFramebuffer(GL_FRAMEBUFFER, target);
    for (const View& view : views) edl_pass_.draw(color_, eye_depth_, view.viewport, settings);
  } else {
    glBlitNamedFramebuffer(framebuffer_, target, 0, 0, width, height, 0, 0, width, height,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, target);
  }
  return stats;
}

std::optional<glm::dvec3> Renderer::pick(int x, int y) const {
  if (!framebuffer_ || x < 0 || y < 0 || x >= width_ || y >= height_) return std::nullopt;
  for (const DrawnView& drawn : last_views_) {
    const Viewport& vp = drawn.view.viewport;
    if (x < vp.x || y < vp.y || x >= vp.x + vp.width || y >= vp.y + vp.height) continue;
    float depth = 0.0f;
    glGetTextureSubImage(depth_, 0, x, y, 0, 1, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, sizeof depth,
                         &depth);
    if (depth <= 0.0f) return std::nullopt;  // the cleared (infinitely far) value
    const Camera& camera = drawn.view.camera;
    const glm::dmat4 inverse =
        glm::inverse(camera.projectionMatrix(vp.aspect(), drawn.range));
    const glm::dvec4 ndc(2.0 * (x + 0.5 - vp.x) / vp.width - 1.0,
                         2.0 * (y + 0.5 - vp.y) / vp.height - 1.0, double(depth), 1.0);
    glm::dvec4 eye = inverse * ndc;
    eye /= eye.w;
    // Eye to world in double: the camera's position may be a UTM coordinate.
    return camera.position + camera.orientation * glm::dvec3(eye);
  }
  return std::nullopt;
}

RenderTarget::RenderTarget(int width, int height) : width_(width), height_(height) {
  assert(width > 0 && height > 0 && "RenderTarget needs a positive size");
  glCreateRenderbuffers(1, &color_);
  glNamedRenderbufferStorage(color_, GL_RGBA8, width, height);
  glCreateFramebuffers(1, &framebuffer_);
  glNamedFramebufferRenderbuffer(framebuffer_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_);
  checkComplete(framebuffer_, "the offscreen");
}

RenderTarget::~RenderTarget() {
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteRenderbuffers(1, &color_);
}

std::vector<std::uint8_t> RenderTarget::readRgba() const {
  const std::size_t row = std::size_t(width_) * 4;
  std::vector<std::uint8_t> bottom_up(row * std::size_t(height_));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  // OpenGL's rows start at the bottom; images (PNG) start at the top.
  std::vector<std::uint8_t> top_down(bottom_up.size());
  for (int y = 0; y < height_; ++y) {
    std::memcpy(top_down.data() + std::size_t(y) * row,
                bottom_up.data() + std::size_t(height_ - 1 - y) * row, row);
  }
  return top_down;
}

}  // namespace parallax
