#include "sim/render/gl_program.h"

#include <vector>

#include "sim/render/gl.h"
#include "sim/render/render_error.h"

namespace culinarycut::render {
namespace {

GLuint Compile(const std::string& program, GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok) return shader;
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::vector<char> log(static_cast<size_t>(length > 0 ? length : 1), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  glDeleteShader(shader);
  throw RenderError("shader program '" + program + "': " + (stage == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                    " shader does not compile: " + log.data());
}

}  // namespace

GlProgram::GlProgram(const std::string& name, const char* vertex_source, const char* fragment_source) : name_(name) {
  const GLuint vertex = Compile(name, GL_VERTEX_SHADER, vertex_source);
  const GLuint fragment = Compile(name, GL_FRAGMENT_SHADER, fragment_source);
  id_ = glCreateProgram();
  glAttachShader(id_, vertex);
  glAttachShader(id_, fragment);
  glLinkProgram(id_);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint ok = GL_FALSE;
  glGetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<size_t>(length > 0 ? length : 1), '\0');
    glGetProgramInfoLog(id_, length, nullptr, log.data());
    glDeleteProgram(id_);
    throw RenderError("shader program '" + name + "' does not link: " + log.data());
  }
}

GlProgram::~GlProgram() { glDeleteProgram(id_); }

void GlProgram::Use() const { glUseProgram(id_); }

int GlProgram::Location(const char* uniform) {
  const auto it = locations_.find(uniform);
  if (it != locations_.end()) return it->second;
  const int location = glGetUniformLocation(id_, uniform);
  locations_.emplace(uniform, location);
  return location;
}

void GlProgram::Set(const char* uniform, int value) { glUniform1i(Location(uniform), value); }
void GlProgram::Set(const char* uniform, float value) { glUniform1f(Location(uniform), value); }
void GlProgram::Set(const char* uniform, const Eigen::Vector3f& value) { glUniform3fv(Location(uniform), 1, value.data()); }
// Eigen is column-major like OpenGL: no transpose.
void GlProgram::Set(const char* uniform, const Eigen::Matrix3f& value) {
  glUniformMatrix3fv(Location(uniform), 1, GL_FALSE, value.data());
}
void GlProgram::Set(const char* uniform, const Eigen::Matrix4f& value) {
  glUniformMatrix4fv(Location(uniform), 1, GL_FALSE, value.data());
}

}  // namespace culinarycut::render
