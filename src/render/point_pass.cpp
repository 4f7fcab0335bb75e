#include "render/point_pass.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <optional>
#include <string>
#include <vector>

#include "render/filter_uniforms.h"
#include "render/frustum.h"
#include "render/point_pass_glsl.h"

namespace parallax {

namespace {

enum Location : GLuint {
  kPosition = 0,
  kColor = 1,
  kNormal = 2,
  kIntensity = 3,
  kClassification = 4,
  kSpacing = 5,
  kFilterWord = 6,
  kGpsTime = 7,
};
enum Binding : GLuint { kPositions = 0, kColors = 1, kNormals = 2, kExtras = 3, kGpsTimes = 4 };

void setAttribute(GLuint vao, GLuint location, bool enabled) {
  if (enabled) {
    glEnableVertexArrayAttrib(vao, location);
  } else {
    glDisableVertexArrayAttrib(vao, location);
  }
}

std::string withDefines(const char* source, const std::string& defines) {
  std::string text(source);
  const auto line_end = text.find('\n') + 1;  // after the #version line, which must come first
  return text.insert(line_end, defines);
}

}  // namespace

const ShaderProgram& PointPass::program(int color, int size, bool lighting, bool orthographic,
                                        bool round, bool eye_depth, unsigned filter) {
  const int key = color | size << 4 | int(lighting) << 8 | int(orthographic) << 9 |
                  int(round) << 10 | int(eye_depth) << 11 | int(filter) << 12;
  auto found = programs_.find(key);
  if (found != programs_.end()) return found->second;
  const std::string vertex_defines = "#define COLOR_MODE " + std::to_string(color) +
                                     "\n#define SIZE_MODE " + std::to_string(size) +
                                     "\n#define LIGHTING " + std::to_string(int(lighting)) +
                                     "\n#define ORTHOGRAPHIC " + std::to_string(int(orthographic)) +
                                     "\n" + filterDefines(filter) + glsl::pointShadingFunctions();
  const std::string fragment_defines = "#define ROUND " + std::to_string(int(round)) +
                                       "\n#define EYE_DEPTH " + std::to_string(int(eye_depth)) +
                                       "\n";
  ShaderProgram compiled(
      {{GL_VERTEX_SHADER, "point_pass.vert", withDefines(glsl::kPointVertex, vertex_defines)},
       {GL_FRAGMENT_SHADER, "point_pass.frag",
        withDefines(glsl::kPointFragment, fragment_defines)}});
  return programs_.emplace(key, std::move(compiled)).first->second;
}

PointPass::PointPass() {
  glCreateVertexArrays(1, &vao_);
  glVertexArrayAttribFormat(vao_, kPosition, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao_, kPosition, kPositions);
  glVertexArrayAttribFormat(vao_, kColor, 4, GL_UNSIGNED_BYTE, GL_TRUE, 0);
  glVertexArrayAttribBinding(vao_, kColor, kColors);
  glVertexArrayAttribFormat(vao_, kNormal, 4, GL_INT_2_10_10_10_REV, GL_TRUE, 0);
  glVertexArrayAttribBinding(vao_, kNormal, kNormals);
  glVertexArrayAttribFormat(vao_, kIntensity, 1, GL_UNSIGNED_SHORT, GL_TRUE, 0);
  glVertexArrayAttribBinding(vao_, kIntensity, kExtras);
  glVertexArrayAttribIFormat(vao_, kClassification, 1, GL_UNSIGNED_BYTE, 2);
  glVertexArrayAttribBinding(vao_, kClassification, kExtras);
  glVertexArrayAttribFormat(vao_, kSpacing, 1, GL_FLOAT, GL_FALSE, 4);
  glVertexArrayAttribBinding(vao_, kSpacing, kExtras);
  glVertexArrayAttribIFormat(vao_, kFilterWord, 1, GL_UNSIGNED_INT, 0);
  glVertexArrayAttribBinding(vao_, kFilterWord, kExtras);
  glVertexArrayAttribFormat(vao_, kGpsTime, 2, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao_, kGpsTime, kGpsTimes);
  glEnableVertexArrayAttrib(vao_, kPosition);
}

PointPass::~PointPass() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

PointPassStats PointPass::draw(const DrawSet& draw_set, std::span<const View> views,
                               std::span<const ClipRange> ranges, const RenderSettings& settings,
                               bool eye_depth) {
  RasterFrame frame;
  frame.draw_set = &draw_set;
  frame.views = views;
  frame.ranges = ranges;
  frame.settings = &settings;
  frame.eye_depth = eye_depth;
  return draw(frame);
}

RasterStats PointPass::draw(const RasterFrame& frame) {
  const DrawSet& draw_set = *frame.draw_set;
  const std::span<const View> views = frame.views;
  const std::span<const ClipRange> ranges = frame.ranges;
  const RenderSettings& settings = *frame.settings;
  const bool eye_depth = frame.eye_depth;
  assert(views.size() == ranges.size() && "PointPass::draw needs one clip range per view");
  assert(views.size() <= kMaxViews && "PointPass::draw draws at most kMaxViews views");
  PointPassStats stats;
  if (draw_set.items.empty() || views.empty()) return stats;

  // Per view: the matrices, the frustum and the point-size scale, computed once per frame.
  struct EyeState {
    glm::dmat4 world_to_eye;
    glm::mat4 projection;
    Frustum frustum;
    float pixels_per_unit;
    Viewport viewport;
  };
  std::vector<EyeState> eyes;
  eyes.reserve(views.size());
  for (std::size_t v = 0; v < views.size(); ++v) {
    const Camera& camera = views[v].camera;
    const glm::dmat4 world_to_eye = camera.viewMatrix();
    const glm::dmat4 projection = camera.projectionMatrix(views[v].aspect(), ranges[v]);
    const int viewport_height = views[v].viewport.height;
    const double pixels_per_unit =
        camera.projection == Projection::Orthographic
            ? viewport_height / camera.ortho_height
            : viewport_height / (2.0 * std::tan(glm::radians(camera.fov_y_deg) / 2));
    eyes.push_back({world_to_eye, glm::mat4(projection), Frustum(projection * world_to_eye),
                    float(pixels_per_unit), views[v].viewport});
  }
  const Camera& camera = views.front().camera;

  // Fall back to a colour the cloud can give: rgb without colours is white, not black.
  ColorMode color = settings.color;
  if ((color == ColorMode::Rgb && !draw_set.has_colors) ||
      (color == ColorMode::Normal && !draw_set.has_normals)) {
    color = ColorMode::Uniform;
  }
  const bool lighting = settings.lighting && draw_set.has_normals;
  const bool orthographic = camera.projection == Projection::Orthographic;
  const bool adaptive = settings.size_mode == PointSizeMode::Adaptive;
  const unsigned filter_parts = filterParts(settings.filter, draw_set);
  const bool filter = filter_parts != 0;

  // Only the attributes this picture needs are fetched: vertex fetch is a large part of the cost
  // of a point on llvmpipe. A disabled attribute reads its constant (set below), never memory.
  setAttribute(vao_, kColor, color == ColorMode::Rgb);
  setAttribute(vao_, kNormal, draw_set.has_normals && (color == ColorMode::Normal || lighting));
  setAttribute(vao_, kIntensity, color == ColorMode::Intensity && draw_set.has_intensity);
  setAttribute(vao_, kClassification,
               color == ColorMode::Classification && draw_set.has_classification);
  setAttribute(vao_, kSpacing, adaptive);
  setAttribute(vao_, kFilterWord,
               (filter_parts & (kFilterClasses | kFilterReturns | kFilterIntensity)) != 0);
  const bool gps_times = (filter_parts & kFilterGps) != 0;
  setAttribute(vao_, kGpsTime, gps_times);
  glVertexAttrib4f(kColor, 1, 1, 1, 1);
  glVertexAttrib4f(kNormal, 0, 0, 1, 0);
  glVertexAttrib1f(kIntensity, 1.0f);
  glVertexAttribI1ui(kClassification, 1);
  glVertexAttrib1f(kSpacing, 0.0f);
  glVertexAttrib2f(kGpsTime, 0.0f, 0.0f);

  const ShaderProgram& shader =
      program(glsl::colorModeDefine(color), int(settings.size_mode), lighting, orthographic,
              settings.shape == PointShape::Round, eye_depth, filter_parts);
  glUseProgram(shader.id());
  glBindVertexArray(vao_);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_GREATER);
  glDepthMask(GL_TRUE);
  glEnable(GL_PROGRAM_POINT_SIZE);
  glDisable(GL_BLEND);
  // Coverage is computed per sample only when asked for: with it off, a point lights exactly
  // the pixels whose centres it covers, also in a multisampled framebuffer.
  if (settings.samples > 1) {
    glEnable(GL_MULTISAMPLE);
  } else {
    glDisable(GL_MULTISAMPLE);
  }

  glUniform3fv(shader.uniform("u_uniform_color"), 1, settings.uniform_color.data());
  glUniform1f(shader.uniform("u_size_px"), settings.point_size_px);
  glUniform1f(shader.uniform("u_world_size"), settings.world_size);
  glUniform1f(shader.uniform("u_adaptive_scale"), settings.adaptive_scale);
  glUniform2f(shader.uniform("u_size_clamp"), settings.min_size_px, settings.max_size_px);
  const GLint projection_location = shader.uniform("u_projection");
  const GLint pixels_per_unit_location = shader.uniform("u_pixels_per_unit");
  const GLint model_view_location = shader.uniform("u_model_view");
  const GLint elevation_location = shader.uniform("u_elevation");
  const GLint node_spacing_location = shader.uniform("u_node_spacing");
  std::optional<FilterUniforms> filter_uniforms;
  if (filter) filter_uniforms.emplace(shader, settings.filter, draw_set);
  const double z_min = draw_set.bounds.min[2];
  const double z_extent = std::max(draw_set.bounds.size()[2], 1e-12);
  // The per-view state is set only when the view changes: with one view, once per frame.
  int current_eye = -1;
  float current_node_spacing = -1.0f;

  const std::size_t last_item = std::min(frame.last_item, draw_set.items.size());
  const std::size_t item_count =
      frame.items.empty() ? (last_item > frame.first_item ? last_item - frame.first_item : 0)
                          : frame.items.size();
  for (std::size_t n = 0; n < item_count; ++n) {
    const DrawItem& item =
        draw_set.items[frame.items.empty() ? frame.first_item + n : frame.items[n]];
    const PointChunk& chunk = *item.chunk;
    std::uint32_t visible = 0;  // bit v: view v sees the chunk
    for (std::size_t v = 0; v < eyes.size(); ++v) {
      if (eyes[v].frustum.intersects(chunk.bounds)) visible |= 1u << v;
    }
    if (!visible) {
      ++stats.chunks_culled;
      continue;
    }
    // Bound once, drawn for every view that sees the chunk.
    glUniform2f(elevation_location, float(chunk.origin.z - z_min), float(1.0 / z_extent));
    if (filter_uniforms) filter_uniforms->setChunk(chunk);
    if (adaptive && item.node_spacing != current_node_spacing) {
      glUniform1f(node_spacing_location, item.node_spacing);
      current_node_spacing = item.node_spacing;
    }
    glVertexArrayVertexBuffer(vao_, kPositions, chunk.buffer, GLintptr(chunk.positions_offset), 12);
    if (draw_set.has_colors) {
      glVertexArrayVertexBuffer(vao_, kColors, chunk.buffer, GLintptr(chunk.colors_offset), 4);
    }
    if (draw_set.has_normals) {
      glVertexArrayVertexBuffer(vao_, kNormals, chunk.buffer, GLintptr(chunk.normals_offset), 4);
    }
    glVertexArrayVertexBuffer(vao_, kExtras, chunk.buffer, GLintptr(chunk.extras_offset), 8);
    if (gps_times) {
      glVertexArrayVertexBuffer(vao_, kGpsTimes, chunk.buffer, GLintptr(chunk.gps_offset), 8);
    }
    for (std::size_t v = 0; v < eyes.size(); ++v) {
      if (!(visible & (1u << v))) continue;
      const EyeState& eye = eyes[v];
      if (int(v) != current_eye) {
        glViewport(eye.viewport.x, eye.viewport.y, eye.viewport.width, eye.viewport.height);
        glUniformMatrix4fv(projection_location, 1, GL_FALSE, glm::value_ptr(eye.projection));
        glUniform1f(pixels_per_unit_location, eye.pixels_per_unit);
        current_eye = int(v);
      }
      // Fold the chunk origin into the matrix in double; the GPU then only sees small numbers.
      const glm::dmat4 model_view = glm::translate(eye.world_to_eye, chunk.origin);
      glUniformMatrix4fv(model_view_location, 1, GL_FALSE, glm::value_ptr(glm::mat4(model_view)));
      glDrawArrays(GL_POINTS, 0, GLsizei(chunk.count));
      ++stats.draw_calls;
    }
    stats.points_drawn += chunk.count;
    ++stats.chunks_drawn;
  }
  glBindVertexArray(0);
  glUseProgram(0);
  return stats;
}

}  // namespace parallax
