#include "sim/render/render_targets.h"

#include <string>

#include "sim/render/gl.h"
#include "sim/render/render_error.h"

namespace culinarycut::render {
namespace {

void CheckComplete(const char* what) {
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw RenderError(std::string(what) + " framebuffer is incomplete (status 0x" + std::to_string(status) +
                      "); the OpenGL driver lacks a needed format (RGBA8, R32F, R32I, depth)");
  }
}

GLuint MakeTexture(GLenum internal_format, GLenum format, GLenum type, int width, int height) {
  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(internal_format), width, height, 0, format, type, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return texture;
}

}  // namespace

CameraTarget::CameraTarget(int width, int height) : width_(width), height_(height) {
  glGenFramebuffers(1, &framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  textures_[0] = MakeTexture(GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, width, height);
  textures_[1] = MakeTexture(GL_R32F, GL_RED, GL_FLOAT, width, height);
  textures_[2] = MakeTexture(GL_R32I, GL_RED_INTEGER, GL_INT, width, height);
  for (int i = 0; i < 3; ++i) {
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + i, GL_TEXTURE_2D, textures_[i], 0);
  }
  glGenRenderbuffers(1, &depth_buffer_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_buffer_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_buffer_);
  const GLenum all[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  glDrawBuffers(3, all);
  CheckComplete("camera");
}

CameraTarget::~CameraTarget() {
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteTextures(3, textures_);
  glDeleteRenderbuffers(1, &depth_buffer_);
}

void CameraTarget::BindAndClear(bool rgb, bool depth, bool segmentation, const float clear_rgb[3]) const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, width_, height_);
  // Unrequested attachments are not written at all: no fill cost, nothing to read.
  const GLenum buffers[] = {rgb ? GLenum(GL_COLOR_ATTACHMENT0) : GLenum(GL_NONE),
                            depth ? GLenum(GL_COLOR_ATTACHMENT1) : GLenum(GL_NONE),
                            segmentation ? GLenum(GL_COLOR_ATTACHMENT2) : GLenum(GL_NONE)};
  glDrawBuffers(3, buffers);
  if (rgb) {
    const GLfloat color[] = {clear_rgb[0], clear_rgb[1], clear_rgb[2], 1.0f};
    glClearBufferfv(GL_COLOR, 0, color);
  }
  if (depth) {
    const GLfloat zero[] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 1, zero);
  }
  if (segmentation) {
    const GLint background[] = {0, 0, 0, 0};
    glClearBufferiv(GL_COLOR, 2, background);
  }
  glClear(GL_DEPTH_BUFFER_BIT);
}

void CameraTarget::ReadRgb(unsigned char* out) const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, out);
}

void CameraTarget::ReadDepth(float* out) const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
  glReadBuffer(GL_COLOR_ATTACHMENT1);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width_, height_, GL_RED, GL_FLOAT, out);
}

void CameraTarget::ReadSegmentation(int* out) const {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
  glReadBuffer(GL_COLOR_ATTACHMENT2);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width_, height_, GL_RED_INTEGER, GL_INT, out);
}

ShadowTarget::ShadowTarget(int size) : size_(size) {
  glGenTextures(1, &texture_);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, size, size, 0, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, nullptr);
  // Hardware depth comparison with bilinear filtering: a 2x2 PCF per tap.
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glGenFramebuffers(1, &framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, texture_, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  CheckComplete("shadow map");
}

ShadowTarget::~ShadowTarget() {
  glDeleteFramebuffers(1, &framebuffer_);
  glDeleteTextures(1, &texture_);
}

void ShadowTarget::BindAndClear() const {
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  glViewport(0, 0, size_, size_);
  glClear(GL_DEPTH_BUFFER_BIT);
}

void ShadowTarget::BindTexture(int unit) const {
  glActiveTexture(GL_TEXTURE0 + unit);
  glBindTexture(GL_TEXTURE_2D, texture_);
}

}  // namespace culinarycut::render
