// The OpenGL side of one render call: a shadow pass shared by all cameras, then per camera a
// colour/depth/segment pass and the read-back of the requested channels. Holds every GL object
// (programs, static meshes per scene and robot, food buffers, framebuffers), so it must be
// created, used and destroyed on the render thread.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "sim/render/camera_images.h"
#include "sim/render/food_surface.h"
#include "sim/render/gl_program.h"
#include "sim/render/gpu_mesh.h"
#include "sim/render/render_scene.h"
#include "sim/render/render_targets.h"
#include "sim/render/robot_visuals.h"
#include "sim/render/scene_geometry.h"

namespace culinarycut::render {

struct FoodDraw {
  const TriangleMesh* mesh = nullptr;
  Material material;
  int segment = kFirstFoodSegment;
};

struct FrameTimings {
  double render_ms = 0.0;    // shadow pass and drawing, until the GPU is done
  double readback_ms = 0.0;  // glReadPixels and row flips
};

class FrameRenderer {
 public:
  explicit FrameRenderer(int shadow_map_size);  // 0 = no shadows
  ~FrameRenderer();

  void SetRobot(RobotVisuals robot);
  const RobotVisuals& robot() const { return robot_; }

  // Renders `cameras` (validated intrinsics in `intrinsics`) into `out`, one entry per camera.
  // Throws RenderError for a robot pose count that does not match or an unknown attached link.
  FrameTimings Render(const RenderScene& scene, const std::vector<FoodDraw>& food,
                      const std::vector<CameraSpec>& cameras, const std::vector<CameraIntrinsics>& intrinsics,
                      std::vector<CameraImages>* out);

 private:
  struct StaticPart {
    std::unique_ptr<GpuMesh> mesh;
    Material material;
    int segment = kBackgroundSegment;
    bool casts_shadow = false;
    int owner = -1;  // robot parts: index into link_poses_world; -1 = world-fixed
    Eigen::Isometry3d in_owner = Eigen::Isometry3d::Identity();
  };
  struct GpuScene {
    std::vector<StaticPart> parts;
    SceneLighting lighting;
  };
  struct DrawItem {
    const GpuMesh* mesh;
    Eigen::Matrix4f model;
    const Material* material;
    int segment;
    bool casts_shadow;
  };

  const GpuScene& SceneFor(const std::string& scene, const SceneLayout& layout);
  // The framebuffer of the slot-th camera of a call at this size.
  CameraTarget& TargetFor(std::size_t slot, int width, int height);
  Eigen::Isometry3d CameraPose(const CameraSpec& camera, const RenderScene& scene) const;
  void CollectDrawItems(const RenderScene& scene, const GpuScene& gpu_scene, const std::vector<FoodDraw>& food);

  GlProgram shadow_program_;
  std::vector<std::unique_ptr<GlProgram>> scene_programs_;  // one per MaterialKind
  std::unique_ptr<ShadowTarget> shadow_;
  RobotVisuals robot_;
  std::vector<StaticPart> robot_parts_;
  std::map<std::string, std::unique_ptr<GpuScene>> scenes_;
  std::map<std::tuple<std::size_t, int, int>, std::unique_ptr<CameraTarget>> targets_;
  std::vector<std::unique_ptr<GpuMesh>> food_meshes_;
  std::vector<DrawItem> draw_items_;  // reused every call
  std::vector<unsigned char> byte_scratch_;  // row flips
  std::vector<float> float_scratch_;
  std::vector<std::int32_t> int_scratch_;
};

}  // namespace culinarycut::render
