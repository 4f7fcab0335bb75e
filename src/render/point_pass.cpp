#include "render/point_pass.h"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <string>

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
};
enum Binding : GLuint { kPositions = 0, kColors = 1, kNormals = 2, kExtras = 3 };

int colorModeIndex(ColorMode mode) {
  switch (mode) {
    case ColorMode::Rgb:
      return 0;
    case ColorMode::Elevation:
      return 1;
    case ColorMode::Intensity:
      return 2;
    case ColorMode::Normal:
      return 3;
    case ColorMode::Classification:
      return 4;
    case ColorMode::Uniform:
      return 5;
  }
  return 5;
}

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
                                        bool round, bool eye_depth) {
  const int key = color | size << 4 | int(lighting) << 8 | int(orthographic) << 9 |
                  int(round) << 10 | int(eye_depth) << 11;
  auto found = programs_.find(key);
  if (found != programs_.end()) return found->second;
  const std::string vertex_defines =
      "#define COLOR_MODE " + std::to_string(color) + "\n#define SIZE_MODE " +
      std::to_string(size) + "\n#define LIGHTING " + std::to_string(int(lighting)) +
      "\n#define ORTHOGRAPHIC " + std::to_string(int(orthographic)) + "\n";
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
  glEnableVertexArrayAttrib(vao_, kPosition);
}

PointPass::~PointPass() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

PointPassStats PointPass::draw(const GpuPointCloud& cloud, const View& view, const ClipRange& range,
                               const RenderSettings& settings, bool eye_depth) {
  PointPassStats stats;
  if (cloud.chunks().empty()) return stats;
  const Camera& camera = view.camera;
  const Viewport& viewport = view.viewport;
  const glm::dmat4 world_to_eye = camera.viewMatrix();
  const glm::dmat4 projection = camera.projectionMatrix(viewport.aspect(), range);
  const Frustum frustum(projection * world_to_eye);

  // Fall back to a colour the cloud can give: rgb without colours is white, not black.
  ColorMode color = settings.color;
  if ((color == ColorMode::Rgb && !cloud.hasColors()) ||
      (color == ColorMode::Normal && !cloud.hasNormals())) {
    color = ColorMode::Uniform;
  }
  const bool lighting = settings.lighting && cloud.hasNormals();
  const bool orthographic = camera.projection == Projection::Orthographic;

  // Only the attributes this picture needs are fetched: vertex fetch is a large part of the cost
  // of a point on llvmpipe. A disabled attribute reads its constant (set below), never memory.
  setAttribute(vao_, kColor, color == ColorMode::Rgb);
  setAttribute(vao_, kNormal, cloud.hasNormals() && (color == ColorMode::Normal || lighting));
  setAttribute(vao_, kIntensity, color == ColorMode::Intensity && cloud.hasIntensity());
  setAttribute(vao_, kClassification,
               color == ColorMode::Classification && cloud.hasClassification());
  setAttribute(vao_, kSpacing, settings.size_mode == PointSizeMode::Adaptive);
  glVertexAttrib4f(kColor, 1, 1, 1, 1);
  glVertexAttrib4f(kNormal, 0, 0, 1, 0);
  glVertexAttrib1f(kIntensity, 1.0f);
  glVertexAttribI1ui(kClassification, 1);
  glVertexAttrib1f(kSpacing, 0.0f);

  const ShaderProgram& shader =
      program(colorModeIndex(color), int(settings.size_mode), lighting, orthographic,
              settings.shape == PointShape::Round, eye_depth);
  glUseProgram(shader.id());
  glBindVertexArray(vao_);
  glViewport(viewport.x, viewport.y, viewport.width, viewport.height);
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

  glUniformMatrix4fv(shader.uniform("u_projection"), 1, GL_FALSE,
                     glm::value_ptr(glm::mat4(projection)));
  glUniform3fv(shader.uniform("u_uniform_color"), 1, settings.uniform_color.data());
  glUniform1f(shader.uniform("u_size_px"), settings.point_size_px);
  glUniform1f(shader.uniform("u_world_size"), settings.world_size);
  glUniform1f(shader.uniform("u_adaptive_scale"), settings.adaptive_scale);
  glUniform2f(shader.uniform("u_size_clamp"), settings.min_size_px, settings.max_size_px);
  const double pixels_per_unit =
      orthographic ? viewport.height / camera.ortho_height
                   : viewport.height / (2.0 * std::tan(glm::radians(camera.fov_y_deg) / 2));
  glUniform1f(shader.uniform("u_pixels_per_unit"), float(pixels_per_unit));
  const GLint model_view_location = shader.uniform("u_model_view");
  const GLint elevation_location = shader.uniform("u_elevation");
  const double z_min = cloud.bounds().min[2];
  const double z_extent = std::max(cloud.bounds().size()[2], 1e-12);

  for (const PointChunk& chunk : cloud.chunks()) {
    if (!frustum.intersects(chunk.bounds)) {
      ++stats.chunks_culled;
      continue;
    }
    // Fold the chunk origin into the matrix in double; the GPU then only sees small numbers.
    const glm::dmat4 model_view = glm::translate(world_to_eye, chunk.origin);
    glUniformMatrix4fv(model_view_location, 1, GL_FALSE, glm::value_ptr(glm::mat4(model_view)));
    glUniform2f(elevation_location, float(chunk.origin.z - z_min), float(1.0 / z_extent));
    glVertexArrayVertexBuffer(vao_, kPositions, chunk.buffer, GLintptr(chunk.positions_offset), 12);
    if (cloud.hasColors()) {
      glVertexArrayVertexBuffer(vao_, kColors, chunk.buffer, GLintptr(chunk.colors_offset), 4);
    }
    if (cloud.hasNormals()) {
      glVertexArrayVertexBuffer(vao_, kNormals, chunk.buffer, GLintptr(chunk.normals_offset), 4);
    }
    glVertexArrayVertexBuffer(vao_, kExtras, chunk.buffer, GLintptr(chunk.extras_offset), 8);
    glDrawArrays(GL_POINTS, 0, GLsizei(chunk.count));
    stats.points_drawn += chunk.count;
    ++stats.chunks_drawn;
  }
  glBindVertexArray(0);
  glUseProgram(0);
  return stats;
}

}  // namespace parallax
