#include "sim/render/frame_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "sim/render/gl.h"
#include "sim/render/render_error.h"
#include "sim/render/shaders.h"

namespace culinarycut::render {
namespace {

using Clock = std::chrono::steady_clock;

double MillisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// A cache key that changes whenever the scene name or any furniture size or position does.
std::string SceneKey(const std::string& scene, const SceneLayout& layout) {
  std::ostringstream key;
  key.precision(17);
  key << scene;
  for (const Eigen::Vector3d* v : {&layout.table_size_m, &layout.table_center_m, &layout.board_size_m,
                                   &layout.board_center_m}) {
    key << ' ' << v->x() << ' ' << v->y() << ' ' << v->z();
  }
  return key.str();
}

// OpenGL orthographic projection of the box [-h, h]^2 x [near, far] in front of the eye.
Eigen::Matrix4f Orthographic(float half_extent, float near_m, float far_m) {
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m(0, 0) = 1.0f / half_extent;
  m(1, 1) = 1.0f / half_extent;
  m(2, 2) = -2.0f / (far_m - near_m);
  m(2, 3) = -(far_m + near_m) / (far_m - near_m);
  return m;
}

// Rows come bottom-up from OpenGL; images are stored top-down.
template <typename T>
void FlipRows(T* data, int width, int height, int channels, std::vector<T>* scratch) {
  const std::size_t row = static_cast<std::size_t>(width) * channels;
  scratch->resize(row);
  for (int top = 0, bottom = height - 1; top < bottom; ++top, --bottom) {
    std::memcpy(scratch->data(), data + top * row, row * sizeof(T));
    std::memcpy(data + top * row, data + bottom * row, row * sizeof(T));
    std::memcpy(data + bottom * row, scratch->data(), row * sizeof(T));
  }
}

constexpr int kMaterialKinds = static_cast<int>(MaterialKind::kEmissive) + 1;

void SetMaterial(GlProgram& program, const Material& material, int segment) {
  program.Set("u_color", material.color);
  program.Set("u_second_color", material.second_color);
  program.Set("u_specular", material.specular);
  program.Set("u_shininess", material.shininess);
  program.Set("u_pattern_scale", material.pattern_scale_m);
  program.Set("u_segment", segment);
}

}  // namespace

FrameRenderer::FrameRenderer(int shadow_map_size)
    : shadow_program_("shadow", kShadowVertexShader, kShadowFragmentShader) {
  for (int kind = 0; kind < kMaterialKinds; ++kind) {
    scene_programs_.push_back(std::make_unique<GlProgram>("scene material " + std::to_string(kind), kSceneVertexShader,
                                                          SceneFragmentShader(kind).c_str()));
  }
  if (shadow_map_size > 0) shadow_ = std::make_unique<ShadowTarget>(shadow_map_size);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_CULL_FACE);  // every mesh is closed and wound counter-clockwise from outside
  glCullFace(GL_BACK);
  glDisable(GL_DITHER);
  glDisable(GL_BLEND);
}

FrameRenderer::~FrameRenderer() = default;

void FrameRenderer::SetRobot(RobotVisuals robot) {
  robot_parts_.clear();
  for (const RobotVisualPart& part : robot.parts) {
    StaticPart gpu;
    gpu.mesh = std::make_unique<GpuMesh>(part.mesh);
    gpu.material = part.material;
    gpu.segment = part.segment;
    gpu.casts_shadow = true;
    gpu.owner = part.owner;
    gpu.in_owner = part.in_owner;
    robot_parts_.push_back(std::move(gpu));
  }
  robot_ = std::move(robot);
}

const FrameRenderer::GpuScene& FrameRenderer::SceneFor(const std::string& scene, const SceneLayout& layout) {
  const std::string key = SceneKey(scene, layout);
  auto it = scenes_.find(key);
  if (it != scenes_.end()) return *it->second;
  if (scenes_.size() >= 16) scenes_.clear();  // many layouts (randomised boards): keep memory bounded
  const SceneGeometry geometry = BuildSceneGeometry(scene, layout);
  auto gpu = std::make_unique<GpuScene>();
  gpu->lighting = geometry.lighting;
  for (const ScenePart& part : geometry.parts) {
    StaticPart gpu_part;
    gpu_part.mesh = std::make_unique<GpuMesh>(part.mesh);
    gpu_part.material = part.material;
    gpu_part.segment = part.segment;
    gpu_part.casts_shadow = part.casts_shadow;
    gpu->parts.push_back(std::move(gpu_part));
  }
  return *scenes_.emplace(key, std::move(gpu)).first->second;
}

CameraTarget& FrameRenderer::TargetFor(std::size_t slot, int width, int height) {
  if (targets_.size() >= 32) targets_.clear();  // many sizes over time: keep memory bounded
  auto& target = targets_[{slot, width, height}];
  if (!target) target = std::make_unique<CameraTarget>(width, height);
  return *target;
}

Eigen::Isometry3d FrameRenderer::CameraPose(const CameraSpec& camera, const RenderScene& scene) const {
  if (camera.attached_link.empty()) return camera.pose_in_world;
  const auto it = robot_.link_frames.find(camera.attached_link);
  if (it == robot_.link_frames.end()) {
    throw RenderError("camera '" + camera.name + "' is attached to link '" + camera.attached_link +
                      "', which the robot (" + robot_.urdf_path + ") does not have");
  }
  if (scene.link_poses_world.empty()) {
    throw RenderError("camera '" + camera.name + "' is attached to link '" + camera.attached_link +
                      "' but the scene has no robot link poses");
  }
  const auto& [owner, link_in_owner] = it->second;
  return scene.link_poses_world[static_cast<std::size_t>(owner)] * link_in_owner * camera.pose_in_world;
}

void FrameRenderer::CollectDrawItems(const RenderScene& scene, const GpuScene& gpu_scene,
                                     const std::vector<FoodDraw>& food) {
  // Roughly front to back (food, robot, board, furniture, walls): the depth test then rejects
  // hidden fragments before shading, which is most of llvmpipe's cost.
  draw_items_.clear();
  while (food_meshes_.size() < food.size()) food_meshes_.push_back(std::make_unique<GpuMesh>());
  for (std::size_t k = 0; k < food.size(); ++k) {
    food_meshes_[k]->Upload(*food[k].mesh);
    draw_items_.push_back({food_meshes_[k].get(), Eigen::Matrix4f::Identity(), &food[k].material, food[k].segment, true});
  }
  if (!scene.link_poses_world.empty()) {
    if (static_cast<int>(scene.link_poses_world.size()) != robot_.pose_count()) {
      throw RenderError("RenderScene::link_poses_world has " + std::to_string(scene.link_poses_world.size()) +
                        " poses; the robot (" + robot_.urdf_path + ") needs " + std::to_string(robot_.pose_count()) +
                        " (base + one per movable link), or none to hide it");
    }
    for (auto it = robot_parts_.rbegin(); it != robot_parts_.rend(); ++it) {  // knife and hand first
      const Eigen::Isometry3d model = scene.link_poses_world[static_cast<std::size_t>(it->owner)] * it->in_owner;
      draw_items_.push_back({it->mesh.get(), model.matrix().cast<float>(), &it->material, it->segment, true});
    }
  }
  for (bool near_work : {true, false}) {
    for (const StaticPart& part : gpu_scene.parts) {
      if (part.casts_shadow != near_work) continue;  // shadow casters are the board and small props
      draw_items_.push_back({part.mesh.get(), Eigen::Matrix4f::Identity(), &part.material, part.segment, part.casts_shadow});
    }
  }
}

FrameTimings FrameRenderer::Render(const RenderScene& scene, const std::vector<FoodDraw>& food,
                                   const std::vector<CameraSpec>& cameras,
                                   const std::vector<CameraIntrinsics>& intrinsics, std::vector<CameraImages>* out) {
  FrameTimings timings;
  const auto render_start = Clock::now();
  std::vector<Eigen::Isometry3d> poses;
  for (const CameraSpec& camera : cameras) poses.push_back(CameraPose(camera, scene));
  const GpuScene& gpu_scene = SceneFor(scene.scene, scene.layout);
  CollectDrawItems(scene, gpu_scene, food);
  const SceneLighting& light = gpu_scene.lighting;

  // One shadow map per call, shared by every camera.
  Eigen::Matrix4f light_view_projection = Eigen::Matrix4f::Identity();
  if (shadow_) {
    const float reach = 3.0f * light.shadow_half_extent_m;
    const Eigen::Vector3d center = light.shadow_center_m.cast<double>();
    const Eigen::Vector3d eye = center + reach * light.direction_to_light.cast<double>();
    const CameraExtrinsics light_frame = ComputeExtrinsics(LookAt(eye, center));
    light_view_projection = Orthographic(light.shadow_half_extent_m, 0.0f, 2.0f * reach) *
                            light_frame.gl_view.cast<float>();
    shadow_->BindAndClear();
    shadow_program_.Use();
    shadow_program_.Set("u_light_view_projection", light_view_projection);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(2.0f, 4.0f);  // slope-scaled bias against shadow acne
    glDisable(GL_CULL_FACE);      // thin boxes (the blade) must shadow from both sides
    for (const DrawItem& item : draw_items_) {
      if (!item.casts_shadow) continue;
      shadow_program_.Set("u_model", item.model);
      item.mesh->Draw();
    }
    glEnable(GL_CULL_FACE);
    glDisable(GL_POLYGON_OFFSET_FILL);
  }

  // Framebuffers first: creating textures rebinds texture unit 0, where the shadow map must stay.
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    const CameraSpec& camera = cameras[c];
    if (camera.rgb || camera.depth || camera.segmentation) TargetFor(c, camera.width, camera.height);
  }
  for (const auto& program : scene_programs_) {
    program->Use();
    program->Set("u_light_view_projection", light_view_projection);
    program->Set("u_direction_to_light", light.direction_to_light);
    program->Set("u_light_color", light.light_color);
    program->Set("u_sky_color", light.sky_color);
    program->Set("u_ground_color", light.ground_color);
    program->Set("u_shadow_map", 0);
    program->Set("u_shadows", shadow_ ? 1 : 0);
  }
  if (shadow_) shadow_->BindTexture(0);
  float clear_rgb[3];
  for (int c = 0; c < 3; ++c) clear_rgb[c] = std::pow(std::min(light.clear_color[c], 1.0f), 1.0f / 2.2f);

  out->resize(cameras.size());
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    const CameraSpec& camera = cameras[c];
    CameraImages& images = (*out)[c];
    images.name = camera.name;
    images.width = camera.width;
    images.height = camera.height;
    images.intrinsics = intrinsics[c];
    images.extrinsics = ComputeExtrinsics(poses[c]);
    if (!camera.rgb && !camera.depth && !camera.segmentation) continue;  // matrices only

    // Every camera draws into its own framebuffer without waiting: llvmpipe rasterises one camera
    // on its worker threads while this thread already sets up the next.
    const CameraTarget& target = TargetFor(c, camera.width, camera.height);
    target.BindAndClear(camera.rgb, camera.depth, camera.segmentation, clear_rgb);
    const Eigen::Matrix4f view = images.extrinsics.gl_view.cast<float>();
    const Eigen::Matrix4f projection = images.intrinsics.gl_projection.cast<float>();
    const Eigen::Vector3f camera_position = poses[c].translation().cast<float>();
    for (const auto& program : scene_programs_) {
      program->Use();
      program->Set("u_view", view);
      program->Set("u_projection", projection);
      program->Set("u_camera_position", camera_position);
    }
    GlProgram* current = nullptr;
    for (const DrawItem& item : draw_items_) {
      GlProgram* program = scene_programs_[static_cast<std::size_t>(item.material->kind)].get();
      if (program != current) program->Use();
      current = program;
      program->Set("u_model", item.model);
      program->Set("u_normal_matrix", Eigen::Matrix3f(item.model.topLeftCorner<3, 3>().inverse().transpose()));
      SetMaterial(*program, *item.material, item.segment);
      item.mesh->Draw();
    }
  }
  glFinish();  // separates drawing from read-back in the timings; the reads would wait anyway
  timings.render_ms = MillisecondsSince(render_start);

  const auto readback_start = Clock::now();
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    const CameraSpec& camera = cameras[c];
    CameraImages& images = (*out)[c];
    if (!camera.rgb && !camera.depth && !camera.segmentation) continue;
    const CameraTarget& target = TargetFor(c, camera.width, camera.height);
    const std::size_t pixels = static_cast<std::size_t>(camera.width) * camera.height;
    if (camera.rgb) {
      images.rgb.resize(3 * pixels);
      target.ReadRgb(images.rgb.data());
      FlipRows(images.rgb.data(), camera.width, camera.height, 3, &byte_scratch_);
    }
    if (camera.depth) {
      images.depth_m.resize(pixels);
      target.ReadDepth(images.depth_m.data());
      FlipRows(images.depth_m.data(), camera.width, camera.height, 1, &float_scratch_);
    }
    if (camera.segmentation) {
      images.segmentation.resize(pixels);
      target.ReadSegmentation(images.segmentation.data());
      FlipRows(images.segmentation.data(), camera.width, camera.height, 1, &int_scratch_);
    }
  }
  timings.readback_ms = MillisecondsSince(readback_start);
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) {
    char code[16];
    std::snprintf(code, sizeof(code), "0x%04x", error);
    throw RenderError(std::string("OpenGL reported error ") + code + " while rendering");
  }
  return timings;
}

}  // namespace culinarycut::render
