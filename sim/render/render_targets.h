// Off-screen framebuffers. A camera target has three colour attachments (0: RGBA8 shaded colour,
// 1: R32F eye depth in metres, 2: R32I segment id) and a depth buffer for the z-test; no
// multisampling, so depth and ids are never blended. The shadow target is one depth texture.
// Lives on the render thread.
#pragma once

namespace culinarycut::render {

class CameraTarget {
 public:
  CameraTarget(int width, int height);  // throws RenderError if the framebuffer is incomplete
  ~CameraTarget();
  CameraTarget(const CameraTarget&) = delete;
  CameraTarget& operator=(const CameraTarget&) = delete;

  // Binds for drawing into only the requested attachments and clears them (colour to `clear_rgb`,
  // depth to 0, segment to 0 = background).
  void BindAndClear(bool rgb, bool depth, bool segmentation, const float clear_rgb[3]) const;
  // Read-back into caller memory; rows come bottom-up (OpenGL order).
  void ReadRgb(unsigned char* out) const;
  void ReadDepth(float* out) const;
  void ReadSegmentation(int* out) const;

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int width_ = 0;
  int height_ = 0;
  unsigned framebuffer_ = 0;
  unsigned textures_[3] = {0, 0, 0};
  unsigned depth_buffer_ = 0;
};

class ShadowTarget {
 public:
  explicit ShadowTarget(int size);
  ~ShadowTarget();
  ShadowTarget(const ShadowTarget&) = delete;
  ShadowTarget& operator=(const ShadowTarget&) = delete;

  void BindAndClear() const;
  void BindTexture(int unit) const;
  int size() const { return size_; }

 private:
  int size_ = 0;
  unsigned framebuffer_ = 0;
  unsigned texture_ = 0;
};

}  // namespace culinarycut::render
