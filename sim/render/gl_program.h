// A linked GLSL program and its uniforms by name. Lives on the render thread.
#pragma once

#include <string>
#include <unordered_map>

#include <Eigen/Core>

namespace culinarycut::render {

class GlProgram {
 public:
  // Compiles and links; throws RenderError with the stage and the compiler's log.
  GlProgram(const std::string& name, const char* vertex_source, const char* fragment_source);
  ~GlProgram();
  GlProgram(const GlProgram&) = delete;
  GlProgram& operator=(const GlProgram&) = delete;

  void Use() const;
  // Uniform setters, `uniform` a string literal; a uniform the compiler removed is ignored.
  void Set(const char* uniform, int value);
  void Set(const char* uniform, float value);
  void Set(const char* uniform, const Eigen::Vector3f& value);
  void Set(const char* uniform, const Eigen::Matrix3f& value);
  void Set(const char* uniform, const Eigen::Matrix4f& value);

 private:
  int Location(const char* uniform);
  unsigned id_ = 0;
  std::string name_;
  // Keyed by the literal's address: uniform names are string literals, and this lookup runs for
  // every uniform of every draw.
  std::unordered_map<const char*, int> locations_;
};

}  // namespace culinarycut::render
