// The server's eyes: renders the scene from the requested cameras, headless through EGL.
//
// Threading: one Renderer per process. It owns one dedicated render thread, which owns the one
// EGL/OpenGL context; Render may be called from any number of threads (the gRPC handlers of many
// sessions). Each call extracts its food surfaces on the calling thread, then posts the GL work
// to the render thread and waits; GL jobs run one at a time in submission order. Static meshes
// (robot, furniture), shaders and framebuffers are shared by all sessions; food meshes are uploaded
// per call. See docs/rendering.md.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/render/camera.h"
#include "sim/render/camera_images.h"
#include "sim/render/egl_context.h"
#include "sim/render/food_surface.h"
#include "sim/render/render_error.h"
#include "sim/render/render_scene.h"

namespace culinarycut::render {

struct RendererOptions {
  EglBackend backend = EglBackend::kAuto;
  std::string robot_urdf_path;   // "" = $CULINARYCUT_ASSETS_DIR/panda/panda_knife.urdf
  int shadow_map_size = 1024;    // texels per side of the one shadow map; 0 = no shadows
  // Food surface extraction; when food_surface.cell_size_m is 0 the cell is this many particle
  // spacings: 2 is the MPM grid spacing at 8 particles per cell, finer than a 224 x 224 camera
  // resolves and 8x fewer cells than 1 spacing.
  FoodSurfaceOptions food_surface;
  float food_cell_size_per_spacing = 2.0f;
};

struct RenderResult {
  std::vector<CameraImages> cameras;  // in the order of the requested cameras
  std::vector<SegmentLabel> labels;   // every id the segmentation images may contain
  double surface_ms = 0.0;            // food surface extraction (calling thread)
  double render_ms = 0.0;             // shadow pass and drawing, waiting for the queue excluded
  double readback_ms = 0.0;           // glReadPixels and row flips
  double wait_ms = 0.0;               // queued behind other sessions' render jobs
};

class Renderer {
 public:
  // Starts the render thread, the EGL context, the shaders and the robot. Throws RenderError with
  // the failed step and what to install, e.g. "EGL could not start: eglInitialize ... failed".
  static std::unique_ptr<Renderer> Create(const RendererOptions& options = {});
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Replaces the robot drawn by later calls. Throws RenderError for an unreadable URDF or mesh.
  void SetRobot(const std::string& urdf_path);
  // [0] = base link, [i + 1] = link moved by movable joint i: the order of link_poses_world.
  std::vector<std::string> robot_pose_link_names() const;

  // Renders the cameras; only requested channels are produced, and a camera with none requested
  // gets only its matrices. Thread-safe. Throws RenderError for a bad camera, scene or food name.
  RenderResult Render(const RenderScene& scene, const std::vector<CameraSpec>& cameras);

  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6, EGL surfaceless"
  std::string device_description() const;
  bool is_software() const;

 private:
  struct Impl;
  explicit Renderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace culinarycut::render
