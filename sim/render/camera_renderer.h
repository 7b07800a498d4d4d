// What renders a scene's cameras, as the engine sees it: an interface with no GL behind it, so the
// world (sim/world) can ask for images without linking EGL, OpenGL, assimp or OpenCV. The headless
// EGL Renderer (renderer.h) implements it; the server creates that one.
#pragma once

#include <vector>

#include "sim/render/camera.h"
#include "sim/render/camera_images.h"
#include "sim/render/render_scene.h"

namespace culinarycut::render {

struct RenderResult {
  std::vector<CameraImages> cameras;  // in the order of the requested cameras
  std::vector<SegmentLabel> labels;   // every id the segmentation images may contain
  double surface_ms = 0.0;            // food surface extraction (calling thread)
  double render_ms = 0.0;             // shadow pass and drawing, waiting for the queue excluded
  double readback_ms = 0.0;           // glReadPixels and row flips
  double wait_ms = 0.0;               // queued behind other sessions' render jobs
};

class CameraRenderer {
 public:
  virtual ~CameraRenderer() = default;
  // Renders the cameras; only requested channels are produced. Throws RenderError.
  virtual RenderResult Render(const RenderScene& scene, const std::vector<CameraSpec>& cameras) = 0;
};

}  // namespace culinarycut::render
