// Renderer throughput (Google Benchmark): three-camera sets (front, left, right; RGB) per second
// with the robot, the board, the scene and a 100k-particle cucumber, food surface extraction
// included, at 224 x 224 and 640 x 480, whole and cut; counters split one set into surface
// extraction, drawing and read-back (ms).
//
//   build/bench/bench_render_throughput --benchmark_counters_tabular=true
//   bench/render_throughput_report.py   (runs it and writes docs/benchmarks/render_throughput.md)
#include <memory>

#include <benchmark/benchmark.h>

#include "bench/render_bench_scenes.h"
#include "sim/render/renderer.h"

namespace culinarycut::render {

Renderer& SharedRenderer() {
  static const std::unique_ptr<Renderer> renderer = Renderer::Create(bench::PandaRendererOptions());
  return *renderer;
}

namespace {

// Args: image side (224: 224 x 224, 640: 640 x 480), cut (0/1), scene (0 table, 1 kitchen),
// channels (0: RGB, 1: RGB + depth + segmentation).
void BM_ThreeCameraSet(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const int height = width == 640 ? 480 : width;
  const bool cut = state.range(1) != 0;
  const SceneLayout layout;
  const bench::FoodParticles food = bench::SampleCucumber(100000, layout, cut);
  RenderScene scene;
  scene.scene = state.range(2) == 0 ? "table" : "kitchen";
  scene.layout = layout;
  scene.link_poses_world = bench::KnifeAt({food.center_m.x(), food.center_m.y(), food.top_z_m + 0.02}, 0.35);
  scene.food = food.View();
  scene.food_names = {"cucumber"};
  auto cameras = DefaultCameras(layout, width, height);
  for (CameraSpec& camera : cameras) camera.depth = camera.segmentation = state.range(3) != 0;
  Renderer& renderer = SharedRenderer();
  renderer.Render(scene, cameras);  // warm-up: static meshes and framebuffers of this size

  double surface_ms = 0.0, render_ms = 0.0, readback_ms = 0.0;
  for (auto _ : state) {
    const RenderResult result = renderer.Render(scene, cameras);
    surface_ms += result.surface_ms;
    render_ms += result.render_ms;
    readback_ms += result.readback_ms;
    benchmark::DoNotOptimize(result.cameras.data());
  }
  const double sets = static_cast<double>(state.iterations());
  state.counters["sets_per_s"] = benchmark::Counter(sets, benchmark::Counter::kIsRate);
  state.counters["surface_ms"] = surface_ms / sets;
  state.counters["render_ms"] = render_ms / sets;
  state.counters["readback_ms"] = readback_ms / sets;
  state.counters["particles"] = static_cast<double>(food.x.size());
  state.counters["food_pieces"] = cut ? 2 : 1;
}
BENCHMARK(BM_ThreeCameraSet)
    ->ArgNames({"side", "cut", "kitchen", "all_channels"})
    ->Args({224, 0, 0, 0})
    ->Args({224, 1, 0, 0})
    ->Args({224, 0, 1, 0})
    ->Args({224, 1, 1, 0})
    ->Args({224, 1, 1, 1})
    ->Args({640, 0, 0, 0})
    ->Args({640, 1, 1, 0})
    ->Args({640, 1, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

}  // namespace
}  // namespace culinarycut::render

int main(int argc, char** argv) {
  // The context (printed before the first benchmark) names the OpenGL renderer that was measured.
  benchmark::AddCustomContext("gl_renderer", culinarycut::render::SharedRenderer().device_description());
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
