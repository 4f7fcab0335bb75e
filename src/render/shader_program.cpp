#include "render/shader_program.h"

#include <utility>

namespace parallax {

namespace {

const char* stageName(GLenum stage) {
  switch (stage) {
    case GL_VERTEX_SHADER:
      return "vertex";
    case GL_FRAGMENT_SHADER:
      return "fragment";
    case GL_COMPUTE_SHADER:
      return "compute";
    case GL_GEOMETRY_SHADER:
      return "geometry";
    default:
      return "unknown";
  }
}

std::string versionLine(const std::string& text) {
  const auto start = text.find("#version");
  if (start == std::string::npos) return "(no #version line)";
  return text.substr(start, text.find('\n', start) - start);
}

std::string driverName() {
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return std::string(renderer ? renderer : "?") + ", OpenGL " + (version ? version : "?");
}

std::string infoLog(GLuint object, bool is_program) {
  GLint length = 0;
  if (is_program) {
    glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length);
  } else {
    glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
  }
  std::string log(std::size_t(length > 0 ? length : 1), '\0');
  if (is_program) {
    glGetProgramInfoLog(object, length, nullptr, log.data());
  } else {
    glGetShaderInfoLog(object, length, nullptr, log.data());
  }
  while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
  return log.empty() ? "(empty log)" : log;
}

}  // namespace

ShaderProgram::ShaderProgram(const std::vector<ShaderSource>& sources) {
  std::vector<GLuint> shaders;
  auto cleanup = [&] {
    for (GLuint shader : shaders) glDeleteShader(shader);
  };
  for (const ShaderSource& source : sources) {
    GLuint shader = glCreateShader(source.stage);
    shaders.push_back(shader);
    const char* text = source.text.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      std::string message = std::string("the ") + stageName(source.stage) + " shader '" +
                            source.name + "' (" + versionLine(source.text) +
                            ") did not compile on " + driverName() + ":\n" + infoLog(shader, false);
      cleanup();
      throw ShaderError(message);
    }
  }
  id_ = glCreateProgram();
  for (GLuint shader : shaders) glAttachShader(id_, shader);
  glLinkProgram(id_);
  cleanup();
  GLint ok = GL_FALSE;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    std::string names;
    for (const ShaderSource& source : sources) names += (names.empty() ? "" : ", ") + source.name;
    std::string message =
        "the program (" + names + ") did not link on " + driverName() + ":\n" + infoLog(id_, true);
    glDeleteProgram(id_);
    id_ = 0;
    throw ShaderError(message);
  }
}

ShaderProgram::~ShaderProgram() {
  if (id_) glDeleteProgram(id_);
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept : id_(std::exchange(other.id_, 0)) {}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
  if (this != &other) {
    if (id_) glDeleteProgram(id_);
    id_ = std::exchange(other.id_, 0);
  }
  return *this;
}

}  // namespace parallax
