#include "render/compute_rasterizer.h"

#include <time.h>
#include <algorithm>
#include <bit>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <numeric>
#include <optional>
#include <span>
#include <string>
#include <thread>

#include "render/compute_rasterizer_glsl.h"
#include "render/filter_uniforms.h"
#include "render/frustum.h"
#include "render/fullscreen_triangle.h"
#include "render/point_pass_glsl.h"

namespace parallax {

namespace {

enum TextureUnit : int {
  kPositions = 0,
  kColors = 1,
  kNormals = 2,
  kExtras = 3,
  kBatches = 4,
  kGpsTimes = 5,
  kTextureUnits = 6,
  // Bound beside the chunk's textures, not re-pointed per chunk.
  kDepthKeys = 6,
  kBatchOrder = 7,
  kIdKeys = 8
};
// SSBO bindings, as in the shaders.
enum Binding : GLuint {
  kDepthBinding = 0,
  kIdBinding = 1,
  kColorBinding = 2,
  kSumBinding = 3,  // to 6
  kFlagBinding = 7,
  kLargeBinding = 8,
};

constexpr std::uint32_t kEmpty = ~0u;
constexpr std::uint32_t kTied = ~1u;  // pass 1's mark of a tied pixel (the shader's TIED_MARK)

bool hasExtension(const char* name) {
  GLint count = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i) {
    const auto* extension = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)));
    if (extension && std::strcmp(extension, name) == 0) return true;
  }
  return false;
}

std::string withDefines(const char* source, const std::string& defines) {
  std::string text(source);
  const std::string marker = "//@DEFINES@\n";
  const auto at = text.find(marker);
  assert(at != std::string::npos && "compute shaders carry a //@DEFINES@ line");
  return text.replace(at, marker.size(), defines);
}

// The variant of a pass, packed into a map key.
struct Variant {
  int pass = 1;  // 1 depth, 2 attributes
  bool atomic64 = false;
  int views = 1;
  int color = 5, size = 0;
  bool lighting = false, orthographic = false, round = false, splat = false;
  bool hq = false, reset = false;
  bool shared_depth = false;  // every view's clip z and w are view 0's (shareDepth)
  bool list_large = false;    // both passes list splats wider than inline_splat (LargeSplats)
  bool large = false;         // the large splats' program
  bool node_spacing = false;  // adaptive sizes from every item's node spacing (NODE_SPACING)
  float max_splat = 1.0f;     // the GL's largest point (one per context: not in the key)
  float inline_splat = 1.0f;  // inlineSplatPx(views): follows from `views`, not in the key
  unsigned filter = 0;        // FilterPart bits (filter_uniforms.h)

  std::uint32_t key() const {
    return std::uint32_t(pass) | std::uint32_t(atomic64) << 2 | std::uint32_t(views) << 3 |
           std::uint32_t(color) << 6 | std::uint32_t(size) << 9 | std::uint32_t(lighting) << 11 |
           std::uint32_t(orthographic) << 12 | std::uint32_t(round) << 13 |
           std::uint32_t(splat) << 14 | std::uint32_t(hq) << 15 | std::uint32_t(reset) << 16 |
           std::uint32_t(shared_depth) << 17 | std::uint32_t(list_large) << 18 |
           std::uint32_t(large) << 19 | std::uint32_t(filter) << 21 |
           std::uint32_t(node_spacing) << 29;
  }
  std::string defines() const {
    // drawPoint writes each view out up to view 3 (DRAW_IN_VIEW, compute_rasterizer_glsl.cpp).
    static_assert(ComputeRasterizer::kMaxViews == 4, "write out every view in drawPoint");
    auto define = [](const char* name, int value) {
      return "#define " + std::string(name) + " " + std::to_string(value) + "\n";
    };
    return define("PASS", pass) + define("ATOMIC64", atomic64) + define("VIEWS", views) +
           define("COLOR_MODE", color) + define("SIZE_MODE", size) + define("LIGHTING", lighting) +
           define("ORTHOGRAPHIC", orthographic) + define("ROUND", round) + define("SPLAT", splat) +
           define("HQ", hq) + define("RESET", reset) + define("SHARED_DEPTH", shared_depth) +
           define("LIST_LARGE", list_large) + define("LARGE", large) +
           define("NODE_SPACING", node_spacing) + filterDefines(filter) + "#define BATCH_POINTS " +
           std::to_string(kBatchPoints) + "u\n#define MAX_SPLAT " + std::to_string(max_splat) +
           "\n#define INLINE_SPLAT " + std::to_string(inline_splat) +
           "\n#define LARGE_SPLATS_PER_GROUP 64u\n#define TIED_MARK " + std::to_string(kTied) +
           "u\n";
  }
};

// Per view, computed once per frame.
struct Eye {
  glm::dmat4 world_to_eye;
  glm::dmat4 projection;
  glm::dmat4 world_to_clip;  // projection * world_to_eye (rows 2, 3 shared: shareDepth)
  Frustum frustum;
  float pixels_per_unit;
  Viewport viewport;
};

// Views whose eyes are parallel and differ by a move in their image plane (an off-axis stereo
// pair; a headset's two eyes, whatever their four fov angles) have the same clip z and w: the
// shader then projects a point's depth once for all views and computes only each view's clip x
// and y (SHARED_DEPTH). Why z and w, and not more: with P_v the asymmetric frustum
//   [a_v 0 c_v 0; 0 e_v f_v 0; 0 0 A B; 0 0 -1 0]
// (A, B from the near and far planes, equal for both eyes: the eyes' depths are equal) and eye v
// at (t_x, t_y, 0) in eye 0's frame, eye v's point is (x - t_x, y - t_y, z, 1), so
//   w_v = -z = w_0, z_v = A z + B = z_0, and, since 1 = (z_0 + A w_0) / B,
//   x_v = a_v (x - t_x) + c_v z = (a_v / a_0) x_0 + (c_v - a_v c_0 / a_0) (-w_0)
//         - (a_v t_x / B) (z_0 + A w_0),
// an affine function of view 0's clip x, z and w (y alike with e, f, t_y). Its three terms cost
// what view v's own row of the model-view-projection costs (four), so the shader takes that row:
// the same arithmetic as a view projected alone, so both ways give the same pixels, bit for bit.
// The condition is tested on the eyes, not on S = P_v W_v (P_0 W_0)^-1 (as until 2026-11-27,
// with row 0 limited to x_0 plus z and w terms, which lost eyes of unequal widths): S's entries
// that carry a depth offset are divided by B, about the near plane, which is tiny where the eye
// stands inside the cloud (a millionth of the far plane), so the rounding of a UTM eye position
// or of a runtime's float poses would fail any fixed tolerance on S. Here: the eyes look the same
// way (forwards within kSharedDepthAngle radians), stand in one plane across it (depth offset
// within kSharedDepthOffset of their distance), and have the same near and far planes (relative
// kSharedDepthRange). Within those, eye v is drawn as if moved by at most 1e-5 of the baseline
// along its view (0.6 um for a 64 mm baseline; a runtime's float poses round to 0.1 um) and
// turned by a microradian: about a thousandth of a pixel for points a few baselines away. View
// v's world-to-clip rows 2 and 3 are then made view 0's, so that the floats sent for them are
// equal and both eyes' depth keys are the same numbers.
constexpr double kSharedDepthAngle = 1e-6;
constexpr double kSharedDepthOffset = 1e-5;
constexpr double kSharedDepthRange = 1e-6;

bool sameDepthAs(const Eye& first, const Eye& eye) {
  const glm::dvec3 first_forward(first.world_to_eye[0][2], first.world_to_eye[1][2],
                                 first.world_to_eye[2][2]);
  const glm::dvec3 forward(eye.world_to_eye[0][2], eye.world_to_eye[1][2], eye.world_to_eye[2][2]);
  if (glm::length(forward - first_forward) > kSharedDepthAngle) return false;
  // Eye v's position in eye 0's frame: its depth offset against the baseline.
  const glm::dvec3 position =
      -glm::transpose(glm::dmat3(eye.world_to_eye)) * glm::dvec3(eye.world_to_eye[3]);
  const glm::dvec3 offset = glm::dvec3(first.world_to_eye * glm::dvec4(position, 1.0));
  if (std::abs(offset.z) > kSharedDepthOffset * glm::length(offset)) return false;
  // Rows 2 and 3 of the projections: z = A z_eye + B, w = C z_eye + D, nothing from x or y.
  const auto close = [](double a, double b) {
    return std::abs(a - b) <= kSharedDepthRange * std::max(std::abs(a), std::abs(b));
  };
  const glm::dmat4& p = eye.projection;
  const glm::dmat4& q = first.projection;
  return p[0][2] == 0.0 && p[1][2] == 0.0 && p[0][3] == 0.0 && p[1][3] == 0.0 &&
         close(p[2][2], q[2][2]) && close(p[3][2], q[3][2]) && p[2][3] == q[2][3] &&
         p[3][3] == q[3][3];
}

bool shareDepth(std::vector<Eye>& eyes) {
  if (eyes.size() < 2) return false;
  for (std::size_t v = 1; v < eyes.size(); ++v) {
    if (!sameDepthAs(eyes[0], eyes[v])) return false;
  }
  for (std::size_t v = 1; v < eyes.size(); ++v) {
    for (int col = 0; col < 4; ++col) {
      eyes[v].world_to_clip[col][2] = eyes[0].world_to_clip[col][2];
      eyes[v].world_to_clip[col][3] = eyes[0].world_to_clip[col][3];
    }
  }
  return true;
}

// The largest size (pixels) a point of `item` may have in any view that sees it, for the
// distance-dependent size modes: from the chunk's largest spacing and its box's nearest depth.
float largestPointSize(const DrawItem& item, const std::vector<Eye>& eyes, std::uint32_t visible,
                       const RenderSettings& settings, const Camera& camera) {
  const PointChunk& chunk = *item.chunk;
  double world = settings.world_size;
  if (settings.size_mode == PointSizeMode::Adaptive) {
    world = (item.node_spacing > 0 ? item.node_spacing : chunk.max_spacing) *
            double(settings.adaptive_scale);
  }
  if (world <= 0) return settings.point_size_px;
  double largest = 0;
  for (std::size_t v = 0; v < eyes.size(); ++v) {
    if (!(visible & (1u << v))) continue;
    double per_unit = eyes[v].pixels_per_unit;
    if (camera.projection == Projection::Perspective) {
      double nearest = INFINITY;
      for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p(corner & 1 ? chunk.bounds.max[0] : chunk.bounds.min[0],
                           corner & 2 ? chunk.bounds.max[1] : chunk.bounds.min[1],
                           corner & 4 ? chunk.bounds.max[2] : chunk.bounds.min[2]);
        nearest = std::min(nearest, -(eyes[v].world_to_eye * glm::dvec4(p, 1.0)).z);
      }
      // The box may reach the eye: then the clamp's maximum is the bound. (A point's depth is
      // at least the nearest corner's, since depth is linear and the box is convex.)
      per_unit = nearest > 1e-9 ? per_unit / nearest : INFINITY;
    }
    largest = std::max(largest, world * per_unit);
  }
  return float(std::clamp(largest, double(settings.min_size_px), double(settings.max_size_px)));
}

double processCpuMs() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return double(now.tv_sec) * 1e3 + double(now.tv_nsec) * 1e-6;
}

// The threads llvmpipe runs a dispatch on (as Mesa sets them: LP_NUM_THREADS, else the CPUs,
// at most 16), or 1 for a GPU, which takes the workgroups in order on all its cores at once.
// A wrong count only costs speed (see the shader's slotOf).
int llvmpipeThreads() {
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  if (!renderer || !std::strstr(renderer, "llvmpipe")) return 1;
  int threads = int(std::thread::hardware_concurrency());
  if (const char* set = std::getenv("LP_NUM_THREADS")) threads = std::atoi(set);
  return std::clamp(threads, 1, 16);
}

}  // namespace

ComputeRasterizer::ComputeRasterizer(const ComputeRasterizerOptions& options) : options_(options) {
  atomic64_ = options.allow_64bit_atomics && hasExtension("GL_NV_shader_atomic_int64") &&
              hasExtension("GL_ARB_gpu_shader_int64");
  cpu_threads_ = llvmpipeThreads();
  glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_ssbo_bytes_);
  // GL_POINTS clamps gl_PointSize to this range; the splats clamp to the same.
  GLfloat point_range[2] = {1.0f, 1.0f};
  glGetFloatv(GL_POINT_SIZE_RANGE, point_range);
  max_point_px_ = std::max(point_range[1], 1.0f);
  glCreateTextures(GL_TEXTURE_BUFFER, kTextureUnits, textures_);
  glCreateTextures(GL_TEXTURE_BUFFER, 6, views_);
  glCreateTextures(GL_TEXTURE_BUFFER, 1, &order_view_);
  glCreateTextures(GL_TEXTURE_BUFFER, 1, &ids_view_);
  glCreateVertexArrays(1, &vao_);
}

ComputeRasterizer::~ComputeRasterizer() {
  glDeleteTextures(kTextureUnits, textures_);
  glDeleteTextures(6, views_);
  glDeleteTextures(1, &order_view_);
  glDeleteTextures(1, &ids_view_);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  const GLuint buffers[] = {depths_, ids_, colors_, sums_, flags_, order_, large_};
  glDeleteBuffers(7, buffers);
}

std::string ComputeRasterizer::unsupported(const RenderSettings& settings, int canvas_width,
                                           int canvas_height) const {
  if (settings.samples > 1) return "multisampling (--msaa) is drawn by GL_POINTS only";
  // One SSBO binding per buffer: 8 bytes a pixel on the 64-bit path, 4 on the other.
  const std::int64_t pixel_bytes = atomic64_ ? 8 : 4;
  const std::int64_t limit =
      std::min<std::int64_t>(max_ssbo_bytes_, std::int64_t(options_.max_range_bytes));
  if (std::int64_t(canvas_width) * canvas_height * pixel_bytes > limit) {
    return "a canvas of " + std::to_string(canvas_width) + "x" + std::to_string(canvas_height) +
           " pixels exceeds one visibility-buffer binding (" + std::to_string(limit >> 20) +
           " MiB)";
  }
  return {};
}

const ShaderProgram& ComputeRasterizer::program(std::uint32_t key, bool resolve) {
  auto& programs = resolve ? resolve_programs_ : programs_;
  return programs.find(key)->second;
}

void ComputeRasterizer::ensureBuffers(int width, int height, bool hq) {
  if (width != width_ || height != height_) {
    const GLuint buffers[] = {depths_, ids_, colors_, sums_};
    glDeleteBuffers(4, buffers);
    depths_ = ids_ = colors_ = sums_ = 0;
    has_sums_ = false;
    width_ = width, height_ = height;
    const GLsizeiptr pixels = GLsizeiptr(width) * height;
    glCreateBuffers(1, &depths_);
    glNamedBufferStorage(depths_, pixels * (atomic64_ ? 8 : 4), nullptr, 0);
    if (!atomic64_) {
      glCreateBuffers(1, &ids_);
      glNamedBufferStorage(ids_, pixels * 4, nullptr, 0);
      glTextureBufferRange(ids_view_, GL_R32UI, ids_, 0, pixels * 4);
    }
    glCreateBuffers(1, &colors_);
    glNamedBufferStorage(colors_, pixels * 4, nullptr, 0);
    glTextureBufferRange(views_[0], atomic64_ ? GL_RG32UI : GL_R32UI, depths_, 0,
                         pixels * (atomic64_ ? 8 : 4));
    glTextureBufferRange(views_[1], GL_R32UI, colors_, 0, pixels * 4);
  }
  if (hq && !has_sums_) {
    // Four planes, each aligned for its own binding range.
    glCreateBuffers(1, &sums_);
    glNamedBufferStorage(sums_, GLsizeiptr(width) * height * 16 + 4 * 256, nullptr, 0);
    has_sums_ = true;
    const GLsizeiptr pixels = GLsizeiptr(width) * height;
    const GLsizeiptr plane = (pixels * 4 + 255) & ~GLsizeiptr(255);
    for (int c = 0; c < 4; ++c) {
      glTextureBufferRange(views_[2 + c], GL_R32UI, sums_, GLintptr(c) * plane, pixels * 4);
    }
  }
}

// The batch flags' bytes per batch: a bit per point (eight words for each of the workgroup's 16
// invocations).
constexpr GLsizeiptr kFlagBytesPerBatch = kBatchPoints / 8;

void ComputeRasterizer::ensureFlags(std::uint32_t batches) {
  if (batches <= flag_capacity_) return;
  if (flags_) glDeleteBuffers(1, &flags_);
  if (order_) glDeleteBuffers(1, &order_);
  flag_capacity_ = std::max(batches, flag_capacity_ * 2);
  glCreateBuffers(1, &flags_);
  glNamedBufferStorage(flags_, GLsizeiptr(flag_capacity_) * kFlagBytesPerBatch, nullptr, 0);
  glCreateBuffers(1, &order_);
  glNamedBufferStorage(order_, GLsizeiptr(flag_capacity_) * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
}

float ComputeRasterizer::inlineSplatPx(std::size_t views) {
  // llvmpipe ends every loop of a shader invocation once all its loops together have run 65 535
  // iterations (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS, one counter shared by every loop): the
  // points after that would be dropped without a word. An invocation walks 256 points, each
  // with a loop over the views and, per view, rows and pixels of an n x n splat: n + n^2 a view,
  // so 256 ((n + n^2) views + views + 1) must stay under it (n = 8 up to 3 views, 7 for 4).
  float n = kInlineSplatPx;
  while (n > 1 && (n + n * n) * float(views) + float(views) + 1 > 255) n -= 1;
  return n;
}

std::uint32_t ComputeRasterizer::largeSplatsPerGroup() const {
  // The records of a group within one SSBO binding, and at least a batch's points in every view
  // (a range is whole batches: the smallest group is one batch).
  const std::int64_t limit =
      std::min<std::int64_t>(max_ssbo_bytes_, std::int64_t(options_.max_range_bytes));
  const std::int64_t smallest = std::int64_t(kBatchPoints) * kMaxViews;
  return std::uint32_t(
      std::max<std::int64_t>(std::min<std::int64_t>((limit - kLargeHeaderBytes) / kLargeSplatBytes,
                                                    options_.large_splats_per_group),
                             smallest));
}

void ComputeRasterizer::ensureLargeSplats() {
  const std::uint32_t capacity = largeSplatsPerGroup();
  if (large_ && capacity == large_capacity_) return;
  if (large_) glDeleteBuffers(1, &large_);
  large_capacity_ = capacity;
  glCreateBuffers(1, &large_);
  glNamedBufferStorage(large_, kLargeHeaderBytes + GLsizeiptr(capacity) * kLargeSplatBytes, nullptr,
                       0);
}

std::uint64_t ComputeRasterizer::largeSplatsOfLastFrame() const {
  if (!listed_large_splats_) return 0;
  std::uint32_t header[2] = {0, 0};
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetNamedBufferSubData(large_, 0, sizeof header, header);
  return header[1];
}

void ComputeRasterizer::clearBuffers(bool hq) {
  const GLsizeiptr pixels = GLsizeiptr(width_) * height_;
  const std::uint32_t empty = kEmpty, zero = 0;
  glClearNamedBufferSubData(depths_, GL_R32UI, 0, pixels * (atomic64_ ? 8 : 4), GL_RED_INTEGER,
                            GL_UNSIGNED_INT, &empty);
  if (ids_) {
    glClearNamedBufferSubData(ids_, GL_R32UI, 0, pixels * 4, GL_RED_INTEGER, GL_UNSIGNED_INT,
                              &empty);
  }
  // The 32-bit path takes the minimum colour of exact ties: start from the largest.
  glClearNamedBufferSubData(colors_, GL_R32UI, 0, pixels * 4, GL_RED_INTEGER, GL_UNSIGNED_INT,
                            &empty);
  if (hq) {
    glClearNamedBufferSubData(sums_, GL_R32UI, 0, GLsizeiptr(width_) * height_ * 16 + 4 * 256,
                              GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  }
}

void ComputeRasterizer::bindBuffers(bool hq) const {
  const GLsizeiptr pixels = GLsizeiptr(width_) * height_;
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, kDepthBinding, depths_, 0,
                    pixels * (atomic64_ ? 8 : 4));
  if (ids_) glBindBufferRange(GL_SHADER_STORAGE_BUFFER, kIdBinding, ids_, 0, pixels * 4);
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, kColorBinding, colors_, 0, pixels * 4);
  if (hq) {
    const GLsizeiptr plane = (pixels * 4 + 255) & ~GLsizeiptr(255);
    for (GLuint c = 0; c < 4; ++c) {
      glBindBufferRange(GL_SHADER_STORAGE_BUFFER, kSumBinding + c, sums_, GLintptr(c) * plane,
                        pixels * 4);
    }
  }
}

namespace {

// Writes into `order` (a slot per batch of the chunk) each range's batches, as indices in their
// range, nearest the eye first by the depth of their centres (chunk-relative, `chunk_to_eye`).
// A chunk without centres keeps its own order.
void orderBatches(const PointChunk& chunk, const glm::dmat4& chunk_to_eye, std::size_t range_points,
                  std::span<std::uint32_t> order) {
  const std::uint32_t range_batches = std::uint32_t(range_points / kBatchPoints);
  std::vector<float> eye_z(chunk.batch_count);
  for (std::uint32_t b = 0; b < chunk.batch_count; ++b) {
    const glm::vec3 c = chunk.batch_centers ? (*chunk.batch_centers)[b] : glm::vec3(0.0f);
    eye_z[b] = float((chunk_to_eye * glm::dvec4(c, 1.0)).z);
  }
  for (std::uint32_t first = 0; first < chunk.batch_count; first += range_batches) {
    const std::uint32_t count = std::min(range_batches, chunk.batch_count - first);
    const auto slots = order.subspan(first, count);
    std::iota(slots.begin(), slots.end(), 0u);
    if (!chunk.batch_centers) continue;
    std::stable_sort(slots.begin(), slots.end(), [&](std::uint32_t a, std::uint32_t b) {
      return eye_z[first + a] > eye_z[first + b];
    });
  }
}

}  // namespace

RasterStats ComputeRasterizer::draw(const RasterFrame& frame) {
  const DrawSet& draw_set = *frame.draw_set;
  const RenderSettings& settings = *frame.settings;
  const std::span<const View> views = frame.views;
  assert(views.size() == frame.ranges.size() && "one clip range per view");
  assert(views.size() <= kMaxViews && "ComputeRasterizer draws at most kMaxViews views");
  assert(unsupported(settings, frame.canvas_width, frame.canvas_height).empty() &&
         "the renderer asks unsupported() first");
  RasterStats stats;
  if (views.empty() || frame.canvas_width <= 0 || frame.canvas_height <= 0) return stats;

  const bool hq = settings.hq;
  pass_times_ = {};
  // With time_passes: glFinish, then the wall and CPU time since the last mark into `wall`, `cpu`.
  auto mark_wall = std::chrono::steady_clock::now();
  double mark_cpu = processCpuMs();
  const auto mark = [&](double& wall, double& cpu) {
    if (!options_.time_passes) return;
    glFinish();
    const auto now = std::chrono::steady_clock::now();
    const double now_cpu = processCpuMs();
    wall = std::chrono::duration<double, std::milli>(now - mark_wall).count();
    cpu = now_cpu - mark_cpu;
    mark_wall = now, mark_cpu = now_cpu;
  };
  mark(pass_times_.clear_ms, pass_times_.clear_cpu_ms);  // what came before: not this frame's
  ensureBuffers(frame.canvas_width, frame.canvas_height, hq);
  if (!frame.accumulate) clearBuffers(hq);

  std::vector<Eye> eyes;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const Camera& camera = views[v].camera;
    const glm::dmat4 world_to_eye = camera.viewMatrix();
    const glm::dmat4 projection = camera.projectionMatrix(views[v].aspect(), frame.ranges[v]);
    const int height = views[v].viewport.height;
    const double pixels_per_unit =
        camera.projection == Projection::Orthographic
            ? height / camera.ortho_height
            : height / (2.0 * std::tan(glm::radians(camera.fov_y_deg) / 2));
    eyes.push_back({world_to_eye, projection, projection * world_to_eye,
                    Frustum(projection * world_to_eye), float(pixels_per_unit), views[v].viewport});
  }
  const Camera& camera = views.front().camera;

  // The same fall-backs as the GL_POINTS pass: rgb without colours is white, not black.
  ColorMode color = settings.color;
  if ((color == ColorMode::Rgb && !draw_set.has_colors) ||
      (color == ColorMode::Normal && !draw_set.has_normals)) {
    color = ColorMode::Uniform;
  }
  Variant variant;
  variant.atomic64 = atomic64_;
  variant.views = int(views.size());
  variant.color = glsl::colorModeDefine(color);
  variant.size = int(settings.size_mode);
  variant.lighting = settings.lighting && draw_set.has_normals;
  variant.orthographic = camera.projection == Projection::Orthographic;
  variant.round = settings.shape == PointShape::Round;
  // 1-pixel squares skip the splat loop; so do sizes below 1 (GL_POINTS rounds them up to 1). A
  // 1-pixel disc does not: GL_POINTS drops it where its centre is off the pixel's by more than
  // half a pixel.
  variant.splat = settings.size_mode != PointSizeMode::Fixed || settings.point_size_px > 1.0f ||
                  settings.shape == PointShape::Round;
  variant.hq = hq;
  variant.reset = frame.accumulate && !atomic64_;
  variant.filter = filterParts(settings.filter, draw_set);
  variant.shared_depth = options_.share_depth && shareDepth(eyes);
  shared_depth_ = variant.shared_depth;
  // Octree nodes size adaptive points by their node's spacing: no per-point spacing to read.
  variant.node_spacing = settings.size_mode == PointSizeMode::Adaptive && !draw_set.items.empty() &&
                         std::all_of(draw_set.items.begin(), draw_set.items.end(),
                                     [](const DrawItem& item) { return item.node_spacing > 0.0f; });
  const bool needs_extras =
      variant.color == 2 || variant.color == 4 ||
      (variant.filter & ~(kFilterElevation | kFilterGps | kFilterPlanes | kFilterPolygon)) != 0 ||
      (settings.size_mode == PointSizeMode::Adaptive && !variant.node_spacing);

  // Ids: the draw set's points in order, whatever this frame draws of it.
  item_ids_.assign(draw_set.items.size() + 1, 0);
  item_chunks_.resize(draw_set.items.size());
  for (std::size_t i = 0; i < draw_set.items.size(); ++i) {
    item_ids_[i + 1] = item_ids_[i] + draw_set.items[i].chunk->count;
    item_chunks_[i] = draw_set.items[i].chunk;
  }
  assert(item_ids_.back() < kTied && "point ids are 32-bit, below the empty and tied marks");

  // The items this frame draws, with the views that see each.
  struct Work {
    std::size_t item;
    std::uint32_t visible;
    double eye_z = 0.0;  // of the chunk's centre in the first view
  };
  std::vector<Work> work;
  // Whether any point may be wider than an inline splat: only then are large splats listed (and
  // the ranges cut to fit the list).
  const float inline_splat = inlineSplatPx(eyes.size());
  bool any_large = variant.splat && settings.size_mode == PointSizeMode::Fixed &&
                   settings.point_size_px > inline_splat;
  const std::size_t last_item = std::min(frame.last_item, draw_set.items.size());
  const std::size_t item_count =
      frame.items.empty() ? (last_item > frame.first_item ? last_item - frame.first_item : 0)
                          : frame.items.size();
  for (std::size_t n = 0; n < item_count; ++n) {
    const std::size_t index = frame.items.empty() ? frame.first_item + n : frame.items[n];
    const DrawItem& item = draw_set.items[index];
    std::uint32_t visible = 0;
    for (std::size_t v = 0; v < eyes.size(); ++v) {
      if (eyes[v].frustum.intersects(item.chunk->bounds)) visible |= 1u << v;
    }
    if (!visible) {
      ++stats.chunks_culled;
      continue;
    }
    if (item.chunk->count == 0) continue;
    if (settings.size_mode != PointSizeMode::Fixed && !any_large) {
      any_large = largestPointSize(item, eyes, visible, settings, camera) > inline_splat;
    }
    work.push_back({index, visible, 0.0});
    stats.points_drawn += item.chunk->count;
    ++stats.chunks_drawn;
  }

  // Chunks nearest the (first) eye first, and within each range its batches too (see
  // t_batch_order in the shader): by the eye-space depth of their centres.
  const glm::dmat4& world_to_eye = eyes.front().world_to_eye;
  for (Work& w : work) {
    const auto center = draw_set.items[w.item].chunk->bounds.center();
    w.eye_z = (world_to_eye * glm::dvec4(center[0], center[1], center[2], 1.0)).z;
  }
  std::stable_sort(work.begin(), work.end(),
                   [](const Work& a, const Work& b) { return a.eye_z > b.eye_z; });

  // Ranges of whole batches, each section within the binding limit (positions are the widest).
  GLint max_texels = 0;
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &max_texels);
  // Where large splats are listed, a range's points in all views fit the list too.
  std::size_t range_limit =
      std::min<std::size_t>(options_.max_range_bytes / 12, std::size_t(max_texels));
  if (any_large)
    range_limit = std::min<std::size_t>(range_limit, largeSplatsPerGroup() / eyes.size());
  const std::size_t range_points =
      std::max<std::size_t>(range_limit / kBatchPoints, 1) * kBatchPoints;

  // The batch flags (see the shader): a bit per point of the work, cleared per frame; and
  // the batches' order, a slot per batch.
  std::vector<std::uint32_t> flag_bases;
  std::uint32_t batch_total = 0;
  for (const Work& w : work) {
    flag_bases.push_back(batch_total);
    batch_total += draw_set.items[w.item].chunk->batch_count;
  }
  ensureFlags(std::max<std::uint32_t>(batch_total, 1));
  const std::uint32_t zero = 0;
  glClearNamedBufferSubData(flags_, GL_R32UI, 0,
                            GLsizeiptr(std::max(batch_total, 1u)) * kFlagBytesPerBatch,
                            GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glBindBufferRange(GL_SHADER_STORAGE_BUFFER, kFlagBinding, flags_, 0,
                    GLsizeiptr(std::max(batch_total, 1u)) * kFlagBytesPerBatch);
  std::vector<std::uint32_t> order(std::max(batch_total, 1u), 0);
  for (std::size_t n = 0; n < work.size(); ++n) {
    const PointChunk& chunk = *draw_set.items[work[n].item].chunk;
    orderBatches(chunk, glm::translate(world_to_eye, chunk.origin), range_points,
                 std::span(order).subspan(flag_bases[n], chunk.batch_count));
  }
  glNamedBufferSubData(order_, 0, GLsizeiptr(order.size()) * 4, order.data());
  glTextureBufferRange(order_view_, GL_R32UI, order_, 0, GLsizeiptr(order.size()) * 4);

  const double z_min = draw_set.bounds.min[2];
  const double z_extent = std::max(draw_set.bounds.size()[2], 1e-12);
  bindBuffers(hq);
  variant.list_large = any_large;
  variant.max_splat = max_point_px_;
  variant.inline_splat = inline_splat;
  if (any_large) {
    ensureLargeSplats();
    // The count and the frame's total start at 0 (the flushes reset the count).
    const std::uint32_t zero_header = 0;
    glClearNamedBufferSubData(large_, GL_R32UI, 0, kLargeHeaderBytes, GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &zero_header);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, kLargeBinding, large_, 0,
                      kLargeHeaderBytes + GLsizeiptr(large_capacity_) * kLargeSplatBytes);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, large_);
  }
  // The views' uniforms, the same for every program of the frame.
  float viewports[4 * kMaxViews], pixels_per_unit[kMaxViews], coeffs[4 * kMaxViews];
  for (std::size_t v = 0; v < eyes.size(); ++v) {
    const Viewport& vp = eyes[v].viewport;
    viewports[4 * v + 0] = float(vp.x), viewports[4 * v + 1] = float(vp.y);
    viewports[4 * v + 2] = float(vp.width), viewports[4 * v + 3] = float(vp.height);
    pixels_per_unit[v] = eyes[v].pixels_per_unit;
    const glm::dmat4& p = eyes[v].projection;
    coeffs[4 * v + 0] = float(p[2][2]), coeffs[4 * v + 1] = float(p[3][2]);
    coeffs[4 * v + 2] = float(p[2][3]), coeffs[4 * v + 3] = float(p[3][3]);
  }
  const GLsizei view_count = GLsizei(eyes.size());
  // A variant's program, compiled on first use.
  const auto compiled = [&](const Variant& v, const char* name) -> const ShaderProgram& {
    const std::uint32_t key = v.key();
    if (!programs_.count(key)) {
      programs_.emplace(
          key, ShaderProgram({{GL_COMPUTE_SHADER, name,
                               withDefines(glsl::kComputeRasterizer,
                                           v.defines() + glsl::pointShadingFunctions())}}));
    }
    return program(key, false);
  };
  // Draws the splats listed since the last flush (variant.pass), on the GPU's own count: a
  // one-invocation program turns it into the indirect dispatch's size (a workgroup a splat) and
  // sets it back to 0, so no count is read back and the list is free for the next ranges.
  const auto flush_large = [&]() {
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    if (!large_args_program_) {
      large_args_program_.emplace(std::vector<ShaderSource>{
          {GL_COMPUTE_SHADER, "compute_rasterizer_large_args.comp", glsl::kLargeSplatArgs}});
    }
    glUseProgram(large_args_program_->id());
    glUniform1ui(large_args_program_->uniform("u_pass"), GLuint(variant.pass));
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    Variant large;
    large.pass = variant.pass;
    large.atomic64 = atomic64_;
    large.views = variant.views;
    large.round = variant.round;
    large.splat = true;
    large.hq = hq;
    large.reset = variant.reset;
    large.list_large = true;
    large.large = true;
    large.max_splat = max_point_px_;
    large.inline_splat = inline_splat;
    const ShaderProgram& shader = compiled(large, "compute_rasterizer_large.comp");
    glUseProgram(shader.id());
    glUniform1i(shader.uniform("u_canvas_width"), frame.canvas_width);
    glUniform1f(shader.uniform("u_hq_range"), settings.hq_depth_range);
    glUniform1ui(shader.uniform("u_large_capacity"), large_capacity_);
    glUniform4fv(shader.uniform("u_viewport"), view_count, viewports);
    glUniform4fv(shader.uniform("u_depth_coeffs"), view_count, coeffs);
    glDispatchComputeIndirect(kLargeArgsOffset);
    // The next ranges list into the same records: this dispatch has read them first.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  };
  // One pass of the points over every range of the work (variant.pass).
  const auto dispatch_points = [&]() {
    const bool needs_colors = variant.pass == 2;
    const ShaderProgram& shader = compiled(variant, "compute_rasterizer.comp");
    glUseProgram(shader.id());
    glUniform1i(shader.uniform("u_canvas_width"), frame.canvas_width);
    glUniform3fv(shader.uniform("u_uniform_color"), 1, settings.uniform_color.data());
    glUniform1f(shader.uniform("u_size_px"), std::max(settings.point_size_px, 1.0f));
    glUniform1f(shader.uniform("u_world_size"), settings.world_size);
    glUniform1f(shader.uniform("u_adaptive_scale"), settings.adaptive_scale);
    glUniform2f(shader.uniform("u_size_clamp"), std::max(settings.min_size_px, 1.0f),
                settings.max_size_px);
    glUniform1f(shader.uniform("u_hq_range"), settings.hq_depth_range);
    glUniform1ui(shader.uniform("u_large_capacity"), large_capacity_);
    // Splats the list holds since its last flush, at most (a point lists once in each view).
    std::size_t listed = 0;
    std::optional<FilterUniforms> filter_uniforms;
    if (variant.filter) filter_uniforms.emplace(shader, settings.filter, draw_set);
    glUniform4fv(shader.uniform("u_viewport"), view_count, viewports);
    glUniform1fv(shader.uniform("u_pixels_per_unit"), view_count, pixels_per_unit);
    glUniform4fv(shader.uniform("u_depth_coeffs"), view_count, coeffs);
    const GLint mvp_location = shader.uniform("u_mvp");
    const GLint model_view_location = shader.uniform("u_model_view");
    const GLint view_mask_location = shader.uniform("u_view_mask");
    const GLint elevation_location = shader.uniform("u_elevation");
    const GLint node_spacing_location = shader.uniform("u_node_spacing");
    const GLint point_count_location = shader.uniform("u_point_count");
    const GLint batch_base_location = shader.uniform("u_batch_base");
    const GLint id_base_location = shader.uniform("u_id_base");
    const GLint flag_base_location = shader.uniform("u_flag_base");
    const GLint run_length_location = shader.uniform("u_run_length");
    glUniform1ui(shader.uniform("u_thread_count"), GLuint(cpu_threads_));
    for (int unit = 0; unit < kTextureUnits; ++unit)
      glBindTextureUnit(GLuint(unit), textures_[unit]);
    if (!atomic64_) {
      glBindTextureUnit(kDepthKeys, views_[0]);
      glBindTextureUnit(kIdKeys, ids_view_);
    }
    glBindTextureUnit(kBatchOrder, order_view_);

    for (std::size_t n = 0; n < work.size(); ++n) {
      const Work& w = work[n];
      const DrawItem& item = draw_set.items[w.item];
      const PointChunk& chunk = *item.chunk;
      glm::mat4 mvp[kMaxViews], model_view[kMaxViews];
      for (std::size_t v = 0; v < eyes.size(); ++v) {
        // The chunk origin is folded in in double: the GPU only sees chunk-sized numbers.
        const glm::dmat4 chunk_to_eye = glm::translate(eyes[v].world_to_eye, chunk.origin);
        model_view[v] = glm::mat4(chunk_to_eye);
        // Shared depth: every view's rows 2 and 3 from the same double rows, so equal floats.
        mvp[v] = variant.shared_depth
                     ? glm::mat4(glm::translate(eyes[v].world_to_clip, chunk.origin))
                     : glm::mat4(eyes[v].projection * chunk_to_eye);
      }
      glUniformMatrix4fv(mvp_location, view_count, GL_FALSE, glm::value_ptr(mvp[0]));
      glUniformMatrix4fv(model_view_location, view_count, GL_FALSE, glm::value_ptr(model_view[0]));
      glUniform1ui(view_mask_location, w.visible);
      glUniform2f(elevation_location, float(chunk.origin.z - z_min), float(1.0 / z_extent));
      glUniform1f(node_spacing_location, item.node_spacing);
      if (filter_uniforms) filter_uniforms->setChunk(chunk);
      glTextureBufferRange(textures_[kBatches], GL_RGBA32F, chunk.buffer,
                           GLintptr(chunk.batches_offset), GLsizeiptr(chunk.batch_count) * 32);
      const std::size_t views_seeing = std::size_t(std::popcount(w.visible));
      for (std::size_t first = 0; first < chunk.count; first += range_points) {
        const std::size_t count = std::min<std::size_t>(range_points, chunk.count - first);
        if (variant.list_large && listed + count * views_seeing > large_capacity_) {
          flush_large();
          glUseProgram(shader.id());
          listed = 0;
        }
        listed += count * views_seeing;
        glTextureBufferRange(textures_[kPositions], GL_RGB32F, chunk.buffer,
                             GLintptr(chunk.positions_offset + first * 12), GLsizeiptr(count * 12));
        if (needs_colors && draw_set.has_colors) {
          glTextureBufferRange(textures_[kColors], GL_RGBA8, chunk.buffer,
                               GLintptr(chunk.colors_offset + first * 4), GLsizeiptr(count * 4));
        }
        if (needs_colors && draw_set.has_normals) {
          glTextureBufferRange(textures_[kNormals], GL_R32UI, chunk.buffer,
                               GLintptr(chunk.normals_offset + first * 4), GLsizeiptr(count * 4));
        }
        if (needs_extras) {
          glTextureBufferRange(textures_[kExtras], GL_RG32UI, chunk.buffer,
                               GLintptr(chunk.extras_offset + first * 8), GLsizeiptr(count * 8));
        }
        if (filter_uniforms && filter_uniforms->readsGpsTime()) {
          glTextureBufferRange(textures_[kGpsTimes], GL_RG32F, chunk.buffer,
                               GLintptr(chunk.gps_offset + first * 8), GLsizeiptr(count * 8));
        }
        glUniform1ui(point_count_location, GLuint(count));
        glUniform1ui(batch_base_location, GLuint(first / kBatchPoints));
        glUniform1ui(id_base_location, GLuint(item_ids_[w.item] + first));
        glUniform1ui(flag_base_location, GLuint(flag_bases[n] + first / kBatchPoints));
        const GLuint groups = GLuint((count + kBatchPoints - 1) / kBatchPoints);
        glUniform1ui(run_length_location, cpu_threads_ > 1 ? groups / GLuint(cpu_threads_) : 0);
        glDispatchCompute(groups, 1, 1);
        if (variant.pass == 1) ++stats.draw_calls;
      }
    }
    if (variant.list_large) flush_large();
  };

  mark(pass_times_.clear_ms, pass_times_.clear_cpu_ms);
  variant.pass = 1;
  dispatch_points();
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  mark(pass_times_.pass1_ms, pass_times_.pass1_cpu_ms);
  variant.pass = 2;
  dispatch_points();
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  mark(pass_times_.pass2_ms, pass_times_.pass2_cpu_ms);
  if (any_large) glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  listed_large_splats_ = any_large;

  // The resolve: the visibility buffer into the bound framebuffer, view by view.
  Variant resolve;
  resolve.atomic64 = atomic64_;
  resolve.hq = hq;
  resolve.orthographic = variant.orthographic;
  const std::uint32_t resolve_key = resolve.key() | std::uint32_t(frame.eye_depth) << 20;
  if (!resolve_programs_.count(resolve_key)) {
    const std::string defines = "#define ATOMIC64 " + std::to_string(int(atomic64_)) +
                                "\n#define HQ " + std::to_string(int(hq)) +
                                "\n#define ORTHOGRAPHIC " +
                                std::to_string(int(variant.orthographic)) + "\n#define EYE_DEPTH " +
                                std::to_string(int(frame.eye_depth)) + "\n";
    resolve_programs_.emplace(
        resolve_key,
        ShaderProgram({{GL_VERTEX_SHADER, "compute_resolve.vert", kFullscreenTriangleVertexShader},
                       {GL_FRAGMENT_SHADER, "compute_resolve.frag",
                        withDefines(glsl::kComputeResolve, defines)}}));
  }
  const ShaderProgram& shader = program(resolve_key, true);
  glUseProgram(shader.id());
  for (GLuint unit = 0; unit < (hq ? 6u : 2u); ++unit) glBindTextureUnit(unit, views_[unit]);
  glUniform1i(shader.uniform("u_canvas_width"), frame.canvas_width);
  const GLint coeffs_location = shader.uniform("u_depth_coeffs");
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GEQUAL);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glBindVertexArray(vao_);
  for (const Eye& eye : eyes) {
    const glm::dmat4& p = eye.projection;
    glUniform4f(coeffs_location, float(p[2][2]), float(p[3][2]), float(p[2][3]), float(p[3][3]));
    glViewport(eye.viewport.x, eye.viewport.y, eye.viewport.width, eye.viewport.height);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  mark(pass_times_.resolve_ms, pass_times_.resolve_cpu_ms);
  return stats;
}

std::optional<PointRef> ComputeRasterizer::pointAt(int x, int y) const {
  if (!depths_ || x < 0 || y < 0 || x >= width_ || y >= height_ || item_chunks_.empty()) {
    return std::nullopt;
  }
  const GLintptr pixel = GLintptr(y) * width_ + x;
  std::uint32_t id = kEmpty, key = kEmpty;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  if (atomic64_) {
    std::uint32_t pair[2];
    glGetNamedBufferSubData(depths_, pixel * 8, 8, pair);
    id = pair[0], key = pair[1];  // little endian: the low word is the id
  } else {
    glGetNamedBufferSubData(depths_, pixel * 4, 4, &key);
    glGetNamedBufferSubData(ids_, pixel * 4, 4, &id);
  }
  if (key == kEmpty || id == kEmpty || id >= item_ids_.back()) return std::nullopt;
  const auto after = std::upper_bound(item_ids_.begin(), item_ids_.end(), std::uint64_t(id));
  PointRef ref;
  ref.item = std::size_t(after - item_ids_.begin()) - 1;
  ref.chunk = item_chunks_[ref.item];
  ref.index = std::uint32_t(id - item_ids_[ref.item]);
  ref.id = id;
  const std::uint32_t bits = ~key;
  std::memcpy(&ref.depth, &bits, 4);
  return ref;
}

}  // namespace parallax
