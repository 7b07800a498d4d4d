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

#include "sim/core/robot_visual_description.h"
#include "sim/render/camera.h"
#include "sim/render/camera_images.h"
#include "sim/render/camera_renderer.h"
#include "sim/render/egl_context.h"
#include "sim/render/food_surface.h"
#include "sim/render/render_error.h"
#include "sim/render/render_scene.h"

namespace culinarycut::render {

struct RendererOptions {
  EglBackend backend = EglBackend::kAuto;
  // The robot to draw, from RobotDescription::visuals (the URDF is parsed once, by sim/robot);
  // empty: no robot.
  RobotVisualDescription robot;
  int shadow_map_size = 1024;    // texels per side of the one shadow map; 0 = no shadows
  // Food surface extraction; when food_surface.cell_size_m is 0 the cell is this many particle
  // spacings: 2 is the MPM grid spacing at 8 particles per cell, finer than a 224 x 224 camera
  // resolves and 8x fewer cells than 1 spacing.
  FoodSurfaceOptions food_surface;
  float food_cell_size_per_spacing = 2.0f;
};

class Renderer final : public CameraRenderer {
 public:
  // Starts the render thread, the EGL context, the shaders and the robot. Throws RenderError with
  // the failed step and what to install, e.g. "EGL could not start: eglInitialize ... failed".
  static std::unique_ptr<Renderer> Create(const RendererOptions& options = {});
  ~Renderer() override;
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Replaces the robot drawn by later calls. Throws RenderError for an unreadable mesh file.
  void SetRobot(const RobotVisualDescription& robot);
  // [0] = base link, [i + 1] = link moved by movable joint i: the order of link_poses_world.
  std::vector<std::string> robot_pose_link_names() const;

  // Renders the cameras; only requested channels are produced, and a camera with none requested
  // gets only its matrices. Thread-safe. Throws RenderError for a bad camera, scene or food name.
  RenderResult Render(const RenderScene& scene, const std::vector<CameraSpec>& cameras) override;

  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6, EGL surfaceless"
  std::string device_description() const;
  bool is_software() const;

 private:
  struct Impl;
  explicit Renderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace culinarycut::render
