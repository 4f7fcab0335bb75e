#include "render/renderer.h"

#include <algorithm>
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

Renderer::Renderer(const ComputeRasterizerOptions& compute_options)
    : compute_options_(compute_options) {}

ComputeRasterizer& Renderer::computeRasterizer() {
  if (!compute_) compute_ = std::make_unique<ComputeRasterizer>(compute_options_);
  return *compute_;
}

RasterizerKind Renderer::chooseRasterizer(const RenderSettings& settings, int width, int height,
                                          Composition composition, std::string* reason) {
  std::string why;
  RasterizerKind kind = RasterizerKind::Points;
  if (settings.rasterizer != RasterizerKind::Points) {
    const int canvas_width = composition == Composition::Direct ? width : 2 * width;
    why = computeRasterizer().unsupported(settings, canvas_width, height);
    if (why.empty()) kind = RasterizerKind::Compute;
  } else if (settings.hq) {
    why = "--hq needs the compute rasterizer: drawn without it";
  }
  if (reason) *reason = why;
  return kind;
}

Renderer::~Renderer() {
  resize(0, 0, 0);
}

int Renderer::samplesFor(const RenderSettings& settings) {
  if (settings.samples <= 1) return 0;
  if (max_samples_ < 0) glGetIntegerv(GL_MAX_SAMPLES, &max_samples_);
  const int samples = std::min(settings.samples, max_samples_);
  return samples > 1 ? samples : 0;
}

void Renderer::resize(int width, int height, int samples) {
  if (width == width_ && height == height_ && samples == samples_) return;
  if (framebuffer_) {
    glDeleteFramebuffers(1, &framebuffer_);
    const GLuint textures[] = {color_, eye_depth_, depth_};
    glDeleteTextures(3, textures);
    framebuffer_ = color_ = eye_depth_ = depth_ = 0;
  }
  if (post_framebuffer_) {
    glDeleteFramebuffers(1, &post_framebuffer_);
    glDeleteTextures(1, &post_color_);
    post_framebuffer_ = post_color_ = 0;
  }
  if (ms_framebuffer_) {
    glDeleteFramebuffers(1, &ms_framebuffer_);
    const GLuint renderbuffers[] = {ms_color_, ms_eye_depth_, ms_depth_};
    glDeleteRenderbuffers(3, renderbuffers);
    ms_framebuffer_ = ms_color_ = ms_eye_depth_ = ms_depth_ = 0;
  }
  width_ = width, height_ = height, samples_ = samples;
  if (width <= 0 || height <= 0) return;
  // Eye depth is RG32F: depth times coverage, and coverage (see EdlPass).
  color_ = makeTexture(GL_RGBA8, width, height);
  eye_depth_ = makeTexture(GL_RG32F, width, height);
  depth_ = makeTexture(GL_DEPTH_COMPONENT32F, width, height);
  glCreateFramebuffers(1, &framebuffer_);
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT0, color_, 0);
  glNamedFramebufferTexture(framebuffer_, GL_COLOR_ATTACHMENT1, eye_depth_, 0);
  glNamedFramebufferTexture(framebuffer_, GL_DEPTH_ATTACHMENT, depth_, 0);
  checkComplete(framebuffer_, "the renderer's");
  if (samples <= 1) return;
  // Renderbuffers: the multisampled images are only drawn into and resolved by blits.
  const auto make_renderbuffer = [&](GLenum format) {
    GLuint renderbuffer = 0;
    glCreateRenderbuffers(1, &renderbuffer);
    glNamedRenderbufferStorageMultisample(renderbuffer, samples, format, width, height);
    return renderbuffer;
  };
  ms_color_ = make_renderbuffer(GL_RGBA8);
  ms_eye_depth_ = make_renderbuffer(GL_RG32F);
  ms_depth_ = make_renderbuffer(GL_DEPTH_COMPONENT32F);
  glCreateFramebuffers(1, &ms_framebuffer_);
  glNamedFramebufferRenderbuffer(ms_framebuffer_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, ms_color_);
  glNamedFramebufferRenderbuffer(ms_framebuffer_, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER,
                                 ms_eye_depth_);
  glNamedFramebufferRenderbuffer(ms_framebuffer_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, ms_depth_);
  checkComplete(ms_framebuffer_, ("the renderer's " + std::to_string(samples) + "-sample").c_str());
}

FrameStats Renderer::render(const GpuPointCloud& cloud, std::span<const View> views,
                            const RenderSettings& settings, GLuint target, int width, int height,
                            Composition composition) {
  return render(cloud.drawSet(), views, settings, target, width, height, composition);
}

FrameStats Renderer::render(const DrawSet& draw_set, std::span<const View> views,
                            const RenderSettings& settings, GLuint target, int width, int height,
                            Composition composition, const FramePart& part) {
  assert((composition == Composition::Direct || views.size() == 2) &&
         "a composed stereo frame has two views, the left eye's first");
  FrameStats stats;
  if (width <= 0 || height <= 0) return stats;
  stats.rasterizer = chooseRasterizer(settings, width, height, composition, &stats.fallback_reason);
  const bool compute = stats.rasterizer == RasterizerKind::Compute;
  const int samples = compute ? 0 : samplesFor(settings);
  // Composed modes draw both eyes full size side by side; the canvas is then twice as wide.
  const int canvas_width = composition == Composition::Direct ? width : 2 * width;
  // Drawing on top of the last picture needs that picture: same canvas, same rasterizer.
  const bool accumulate = part.accumulate && width_ == canvas_width && height_ == height &&
                          samples_ == samples && last_rasterizer_ == stats.rasterizer &&
                          last_composition_ == composition;
  resize(canvas_width, height, samples);

  const GLuint draw_framebuffer = samples > 1 ? ms_framebuffer_ : framebuffer_;
  glBindFramebuffer(GL_FRAMEBUFFER, draw_framebuffer);
  glDisable(GL_SCISSOR_TEST);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(draw_framebuffer, 2, both);
  const float background[] = {settings.background[0], settings.background[1],
                              settings.background[2], 1.0f};
  const float zero[] = {0.0f, 0.0f, 0.0f, 0.0f};
  const float far_depth = 0.0f;  // reversed depth: 0 is infinitely far
  if (!accumulate) {
    glClearNamedFramebufferfv(draw_framebuffer, GL_COLOR, 0, background);
    // Eye depth is read by eye-dome lighting only: clearing 8 bytes a pixel for nothing costs
    // several milliseconds at 1080p on llvmpipe (twice that for a double-width stereo canvas).
    if (settings.edl) glClearNamedFramebufferfv(draw_framebuffer, GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(draw_framebuffer, GL_DEPTH, 0, &far_depth);
  }
  // Writing eye depth costs a store per fragment: only when eye-dome lighting reads it. Picking
  // reads the depth buffer, which is always written.
  glNamedFramebufferDrawBuffers(draw_framebuffer, settings.edl ? 2 : 1, both);
  // A round point's disc is cut by a per-fragment discard: only shading every sample smooths its
  // edge (a square's edge is smoothed by the coverage alone, at no extra cost).
  const bool sample_shading = samples > 1 && settings.shape == PointShape::Round;
  if (sample_shading) {
    glEnable(GL_SAMPLE_SHADING);
    glMinSampleShading(1.0f);
  }

  glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
  last_views_.clear();
  std::vector<ClipRange> ranges;
  for (const View& view : views) {
    const ClipRange range = view.camera.clipRange(draw_set.bounds);
    ranges.push_back(range);
    last_views_.push_back({view, range});
  }
  // One pass over the chunks for all views: culled once, bound once, drawn per view (GL_POINTS)
  // or read once and projected into every view (compute).
  RasterFrame raster;
  raster.draw_set = &draw_set;
  raster.views = views;
  raster.ranges = ranges;
  raster.settings = &settings;
  raster.eye_depth = settings.edl;
  raster.canvas_width = canvas_width;
  raster.canvas_height = height;
  raster.first_item = part.first_item;
  raster.last_item = part.last_item;
  raster.accumulate = accumulate;
  const RasterStats pass = compute ? computeRasterizer().draw(raster) : point_pass_.draw(raster);
  stats.points_drawn = pass.points_drawn;
  stats.chunks_drawn = pass.chunks_drawn;
  stats.chunks_culled = pass.chunks_culled;
  stats.draw_calls = pass.draw_calls;
  last_rasterizer_ = stats.rasterizer;
  glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
  if (sample_shading) glDisable(GL_SAMPLE_SHADING);
  if (samples > 1) resolve(settings.edl);
  last_edl_ = settings.edl;
  last_composition_ = composition;
  composite(views, settings, target, width, height, composition);
  return stats;
}

void Renderer::resolve(bool eye_depth) {
  // A blit writes the read buffer into every draw buffer: one attachment at a time. Depth is
  // copied from one sample per pixel (blits of depth are always NEAREST), enough for picking.
  const GLenum first[] = {GL_COLOR_ATTACHMENT0};
  glNamedFramebufferReadBuffer(ms_framebuffer_, GL_COLOR_ATTACHMENT0);
  glNamedFramebufferDrawBuffers(framebuffer_, 1, first);
  glBlitNamedFramebuffer(ms_framebuffer_, framebuffer_, 0, 0, width_, height_, 0, 0, width_,
                         height_, GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT, GL_NEAREST);
  if (eye_depth) {
    const GLenum second[] = {GL_NONE, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferReadBuffer(ms_framebuffer_, GL_COLOR_ATTACHMENT1);
    glNamedFramebufferDrawBuffers(framebuffer_, 2, second);
    glBlitNamedFramebuffer(ms_framebuffer_, framebuffer_, 0, 0, width_, height_, 0, 0, width_,
                           height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glNamedFramebufferReadBuffer(ms_framebuffer_, GL_COLOR_ATTACHMENT0);
    glNamedFramebufferDrawBuffers(framebuffer_, 1, first);
  }
}

void Renderer::ensurePostTarget() {
  if (post_framebuffer_) return;
  post_color_ = makeTexture(GL_RGBA8, width_, height_);
  glCreateFramebuffers(1, &post_framebuffer_);
  glNamedFramebufferTexture(post_framebuffer_, GL_COLOR_ATTACHMENT0, post_color_, 0);
  checkComplete(post_framebuffer_, "the renderer's stereo post-processing");
}

bool Renderer::composite(std::span<const View> views, const RenderSettings& settings, GLuint target,
                         int width, int height, Composition composition) {
  const int canvas_width = composition == Composition::Direct ? width : 2 * width;
  if (!framebuffer_ || canvas_width != width_ || height != height_ ||
      composition != last_composition_) {
    return false;
  }
  // Eye depth exists only when the points were drawn for eye-dome lighting.
  const bool edl = settings.edl && last_edl_;
  if (composition == Composition::Direct) {
    if (edl) {
      glBindFramebuffer(GL_FRAMEBUFFER, target);
      for (const View& view : views) edl_pass_.draw(color_, eye_depth_, view.viewport, settings);
    } else {
      glBlitNamedFramebuffer(framebuffer_, target, 0, 0, width, height, 0, 0, width, height,
                             GL_COLOR_BUFFER_BIT, GL_NEAREST);
      glBindFramebuffer(GL_FRAMEBUFFER, target);
    }
    // The target's pixels are the canvas's: the overlay goes straight on top.
    drawOverlay();
    return true;
  }
  // Composed stereo: eye-dome lighting per eye into the post canvas, the overlay per eye on it,
  // then the composition. The overlay needs a canvas of its own (the points' canvas is kept as
  // drawn, for the next composite()).
  GLuint canvas = color_, canvas_framebuffer = framebuffer_;
  if (edl || !overlay_.empty()) {
    ensurePostTarget();
    glBindFramebuffer(GL_FRAMEBUFFER, post_framebuffer_);
    if (edl) {
      for (const View& view : views) edl_pass_.draw(color_, eye_depth_, view.viewport, settings);
    } else {
      glBlitNamedFramebuffer(framebuffer_, post_framebuffer_, 0, 0, width_, height_, 0, 0, width_,
                             height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    drawOverlay();
    canvas = post_color_, canvas_framebuffer = post_framebuffer_;
  }
  if (!compositor_) compositor_.emplace();
  compositor_->compose(composition, canvas, canvas_framebuffer, target, width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, target);
  return true;
}

void Renderer::drawOverlay() {
  if (overlay_.empty() || last_views_.empty()) return;
  if (!overlay_pass_) overlay_pass_ = std::make_unique<OverlayPass>();
  std::vector<View> views;
  std::vector<ClipRange> ranges;
  for (const DrawnView& drawn : last_views_) {
    views.push_back(drawn.view);
    ranges.push_back(drawn.range);
  }
  overlay_pass_->draw(overlay_, views, ranges, depth_, width_, height_, overlay_depth_);
}

std::optional<glm::dvec3> Renderer::pick(int x, int y) const {
  const auto picked = pickPoint(x, y);
  if (!picked) return std::nullopt;
  return picked->position;
}

std::optional<PickedPoint> Renderer::pickPoint(int x, int y) const {
  if (!framebuffer_ || x < 0 || y < 0 || x >= width_ || y >= height_) return std::nullopt;
  for (std::size_t v = 0; v < last_views_.size(); ++v) {
    const DrawnView& drawn = last_views_[v];
    const Viewport& vp = drawn.view.viewport;
    if (x < vp.x || y < vp.y || x >= vp.x + vp.width || y >= vp.y + vp.height) continue;
    float depth = 0.0f;
    glGetTextureSubImage(depth_, 0, x, y, 0, 1, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, sizeof depth,
                         &depth);
    if (depth <= 0.0f) return std::nullopt;  // the cleared (infinitely far) value
    PickedPoint picked;
    picked.view = int(v);
    if (last_rasterizer_ == RasterizerKind::Compute && compute_) {
      // The visibility buffer names the point, unless a GL_POINTS fall-back drew nearer.
      const auto point = compute_->pointAt(x, y);
      if (point && point->depth == depth) {
        float relative[3];
        glGetNamedBufferSubData(point->chunk->buffer,
                                GLintptr(point->chunk->positions_offset + 12 * point->index), 12,
                                relative);
        picked.point = point;
        picked.position = point->chunk->origin + glm::dvec3(relative[0], relative[1], relative[2]);
        return picked;
      }
    }
    const Camera& camera = drawn.view.camera;
    const glm::dmat4 inverse =
        glm::inverse(camera.projectionMatrix(drawn.view.aspect(), drawn.range));
    const glm::dvec4 ndc(2.0 * (x + 0.5 - vp.x) / vp.width - 1.0,
                         2.0 * (y + 0.5 - vp.y) / vp.height - 1.0, double(depth), 1.0);
    glm::dvec4 eye = inverse * ndc;
    eye /= eye.w;
    // Eye to world in double: the camera's position may be a UTM coordinate.
    picked.position = camera.position + camera.orientation * glm::dvec3(eye);
    return picked;
  }
  return std::nullopt;
}

int Renderer::viewAt(int x, int y) const {
  for (std::size_t v = 0; v < last_views_.size(); ++v) {
    const Viewport& vp = last_views_[v].view.viewport;
    if (x >= vp.x && y >= vp.y && x < vp.x + vp.width && y < vp.y + vp.height) return int(v);
  }
  return -1;
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
