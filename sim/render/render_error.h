// The one exception type of the renderer: every failure to start (EGL, GL, shaders) or to render
// (bad camera, bad scene input) throws it, with a message a person can act on.
#pragma once

#include <stdexcept>
#include <string>

namespace culinarycut::render {

class RenderError : public std::runtime_error {
 public:
  explicit RenderError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace culinarycut::render
