#include "sim/render/renderer.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "sim/core/assets.h"
#include "sim/render/food_palette.h"
#include "sim/render/frame_renderer.h"
#include "sim/render/render_thread.h"
#include "sim/render/robot_visuals.h"

namespace culinarycut::render {
namespace {

using Clock = std::chrono::steady_clock;

double MillisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::vector<SegmentLabel> FixedLabels() {
  return {{kBackgroundSegment, "background", -1, -1, ""},
          {kRobotSegment, "robot", -1, -1, ""},
          {kKnifeSegment, "knife", -1, -1, ""},
          {kBoardSegment, "board", -1, -1, ""}};
}

Material FoodMaterial(const std::string& food) {
  const FoodColors& colors = FoodPalette(food);
  Material material;
  material.kind = MaterialKind::kFood;
  material.color = colors.skin;
  material.second_color = colors.flesh;
  material.specular = 0.25f;
  material.shininess = 40.0f;
  return material;
}

}  // namespace

struct Renderer::Impl {
  RendererOptions options;
  // Created and destroyed on the render thread; the thread is declared last so it stops first.
  std::unique_ptr<EglContext> context;
  std::unique_ptr<FrameRenderer> frame_renderer;
  std::string description;
  bool software = false;
  std::unique_ptr<RenderThread> thread;
};

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Renderer::~Renderer() {
  if (impl_ && impl_->thread) {
    // GL objects and the context go on the thread that owns them.
    impl_->thread->Run<void>([impl = impl_.get()] {
      impl->frame_renderer.reset();
      impl->context.reset();
    });
    impl_->thread.reset();
  }
}

std::unique_ptr<Renderer> Renderer::Create(const RendererOptions& options) {
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  if (options.shadow_map_size < 0) throw RenderError("RendererOptions::shadow_map_size must be >= 0");
  RobotVisuals robot = BuildRobotVisuals(options.robot);  // CPU work, before any GL
  Impl* raw = impl.get();
  impl->thread = std::make_unique<RenderThread>([raw, &robot] {
    try {
      raw->context = EglContext::Create(raw->options.backend);
      raw->description = raw->context->description();
      raw->software = raw->context->is_software();
      raw->frame_renderer = std::make_unique<FrameRenderer>(raw->options.shadow_map_size);
      raw->frame_renderer->SetRobot(std::move(robot));
    } catch (...) {
      raw->frame_renderer.reset();  // GL objects die with their context, on this thread
      raw->context.reset();
      throw;
    }
  });
  return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

void Renderer::SetRobot(const RobotVisualDescription& description) {
  RobotVisuals robot = BuildRobotVisuals(description);
  impl_->thread->Run<void>([this, &robot] { impl_->frame_renderer->SetRobot(std::move(robot)); });
}

std::vector<std::string> Renderer::robot_pose_link_names() const {
  return impl_->thread->Run<std::vector<std::string>>(
      [this] { return impl_->frame_renderer->robot().owner_names; });
}

std::string Renderer::device_description() const { return impl_->description; }
bool Renderer::is_software() const { return impl_->software; }

RenderResult Renderer::Render(const RenderScene& scene, const std::vector<CameraSpec>& cameras) {
  RenderResult result;
  result.labels = FixedLabels();
  bool any_channel = false;
  std::vector<CameraIntrinsics> intrinsics;
  for (const CameraSpec& camera : cameras) {
    intrinsics.push_back(ComputeIntrinsics(camera));  // validates before any work
    any_channel = any_channel || camera.rgb || camera.depth || camera.segmentation;
  }
  if (cameras.empty()) return result;

  // Food surfaces on the calling thread: sessions extract in parallel, only GL is serialised.
  std::vector<FoodPieceSurface> surfaces;
  const auto surface_start = Clock::now();
  if (any_channel && scene.food.count > 0) {
    try {
      FoodSurfaceOptions surface_options = impl_->options.food_surface;
      if (surface_options.cell_size_m == 0.0f && scene.food.particle_spacing_m > 0.0f) {
        surface_options.cell_size_m =
            std::max(0.001f, impl_->options.food_cell_size_per_spacing * scene.food.particle_spacing_m);
      }
      surfaces = ExtractFoodSurfaces(scene.food, surface_options);
    } catch (const std::invalid_argument& error) {
      throw RenderError(std::string("food surface extraction failed: ") + error.what());
    }
  }
  result.surface_ms = MillisecondsSince(surface_start);
  std::vector<FoodDraw> food;
  for (std::size_t k = 0; k < surfaces.size(); ++k) {
    const FoodPieceSurface& surface = surfaces[k];
    if (surface.object >= scene.food_names.size()) {
      throw RenderError("food object " + std::to_string(surface.object) +
                        " has no name in RenderScene::food_names (size " + std::to_string(scene.food_names.size()) + ")");
    }
    const std::string& name = scene.food_names[surface.object];
    const int segment = kFirstFoodSegment + static_cast<int>(k);
    food.push_back({&surface.mesh, FoodMaterial(name), segment});
    result.labels.push_back({segment, "food", surface.object, surface.piece, name});
  }

  const auto queued = Clock::now();
  double wait_ms = 0.0;
  const FrameTimings timings = impl_->thread->Run<FrameTimings>([&] {
    wait_ms = MillisecondsSince(queued);
    return impl_->frame_renderer->Render(scene, food, cameras, intrinsics, &result.cameras);
  });
  result.wait_ms = wait_ms;
  result.render_ms = timings.render_ms;
  result.readback_ms = timings.readback_ms;
  return result;
}

}  // namespace culinarycut::render
