// A linked GLSL program built from embedded sources, with errors a user can act on.
#pragma once

#include <epoxy/gl.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace parallax {

struct ShaderSource {
  GLenum stage = GL_VERTEX_SHADER;
  std::string name;  // where the text comes from, for messages: "point_pass.vert"
  std::string text;  // complete GLSL, #version line first
};

// A shader failed to compile or a program to link. The message names the stage, the shader's
// name, the GLSL version it asked for, the driver and the driver's log.
class ShaderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Owns one GL program object. Needs a current context for its whole life.
class ShaderProgram {
 public:
  ShaderProgram() = default;
  explicit ShaderProgram(const std::vector<ShaderSource>& sources);
  ~ShaderProgram();
  ShaderProgram(ShaderProgram&& other) noexcept;
  ShaderProgram& operator=(ShaderProgram&& other) noexcept;
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  GLuint id() const { return id_; }
  // -1 when the uniform is absent or optimised away (setting it is then a no-op in GL).
  GLint uniform(const char* name) const { return glGetUniformLocation(id_, name); }

 private:
  GLuint id_ = 0;
};

}  // namespace parallax
