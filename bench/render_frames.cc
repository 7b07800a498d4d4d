// Writes what the cameras see to PNG files, for docs/images: the front, left and right views side
// by side for the table and kitchen scenes with a whole and a cut cucumber, the wrist view, and
// the depth and segmentation channels of one view.
//
//   build/bench/bench_render_frames docs/images
#include <algorithm>
#include <cstdio>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bench/render_bench_scenes.h"
#include "sim/render/renderer.h"

namespace culinarycut::render {
namespace {

cv::Mat ToBgr(const CameraImages& images) {
  cv::Mat rgb(images.height, images.width, CV_8UC3, const_cast<std::uint8_t*>(images.rgb.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

cv::Mat DepthColormap(const CameraImages& images) {
  cv::Mat depth(images.height, images.width, CV_32FC1, const_cast<float*>(images.depth_m.data()));
  cv::Mat scaled;
  depth.convertTo(scaled, CV_8UC1, -255.0 / 2.0, 255.0);  // 0 m white .. 2 m black
  cv::Mat colored;
  cv::applyColorMap(scaled, colored, cv::COLORMAP_INFERNO);
  return colored;
}

cv::Mat SegmentationColormap(const CameraImages& images) {
  static const cv::Vec3b palette[] = {{40, 40, 40}, {200, 200, 200}, {60, 200, 255}, {40, 110, 180},
                                      {60, 220, 60}, {230, 80, 230}, {255, 160, 40}, {40, 40, 230}};
  cv::Mat out(images.height, images.width, CV_8UC3);
  for (int v = 0; v < images.height; ++v) {
    for (int u = 0; u < images.width; ++u) {
      const int id = images.segmentation[static_cast<std::size_t>(v) * images.width + u];
      out.at<cv::Vec3b>(v, u) = palette[std::min(id, 7)];
    }
  }
  return out;
}

void Write(const std::string& path, const cv::Mat& image) {
  if (!cv::imwrite(path, image, {cv::IMWRITE_PNG_COMPRESSION, 9})) {
    throw RenderError("cannot write " + path);
  }
  std::printf("wrote %s\n", path.c_str());
}

}  // namespace
}  // namespace culinarycut::render

int main(int argc, char** argv) {
  using namespace culinarycut::render;
  const std::string out_dir = argc > 1 ? argv[1] : "docs/images";
  try {
    auto renderer = Renderer::Create(bench::PandaRendererOptions());
    std::printf("renderer: %s\n", renderer->device_description().c_str());
    const culinarycut::SceneLayout layout;
    for (const bool cut : {false, true}) {
      const bench::FoodParticles food = bench::SampleCucumber(100000, layout, cut);
      const double yaw = 0.35;
      const Eigen::Vector3d edge = cut ? Eigen::Vector3d(food.center_m.x(), food.center_m.y(), 0.025)
                                       : Eigen::Vector3d(food.center_m.x(), food.center_m.y(), food.top_z_m + 0.06);
      RenderScene scene;
      scene.layout = layout;
      scene.link_poses_world = bench::KnifeAt(edge, yaw);
      scene.food = food.View();
      scene.food_names = {"cucumber"};
      for (const std::string& name : {std::string("table"), std::string("kitchen")}) {
        scene.scene = name;
        auto cameras = DefaultCameras(layout, 400, 300);
        cameras.push_back(WristCamera(400, 300));
        for (auto& camera : cameras) camera.depth = camera.segmentation = true;
        const RenderResult result = renderer->Render(scene, cameras);
        cv::Mat row;
        cv::hconcat(std::vector<cv::Mat>{ToBgr(result.cameras[0]), ToBgr(result.cameras[1]), ToBgr(result.cameras[2])},
                    row);
        const std::string stem = out_dir + "/render_" + name + "_" + (cut ? "cut" : "whole");
        Write(stem + "_front_left_right.png", row);
        if (cut) Write(stem + "_wrist.png", ToBgr(result.cameras[3]));
        if (cut && name == "kitchen") {
          cv::Mat channels;
          cv::hconcat(std::vector<cv::Mat>{ToBgr(result.cameras[0]), DepthColormap(result.cameras[0]),
                                           SegmentationColormap(result.cameras[0])},
                      channels);
          Write(out_dir + "/render_channels_front.png", channels);
        }
      }
    }
    // Close-up of the cut faces: pieces pushed 3 cm apart, the knife lifted.
    const bench::FoodParticles food = bench::SampleCucumber(100000, layout, true, 0.015);
    RenderScene scene;
    scene.scene = "kitchen";
    scene.layout = layout;
    scene.link_poses_world = bench::KnifeAt(food.center_m + Eigen::Vector3d(0, 0, 0.12), 0.35);
    scene.food = food.View();
    scene.food_names = {"cucumber"};
    const Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(food.axis);
    CameraSpec closeup;
    closeup.name = "closeup";
    closeup.pose_in_world = LookAt(food.center_m - 0.16 * side + 0.08 * food.axis + Eigen::Vector3d(0, 0, 0.09),
                                   food.center_m - 0.01 * food.axis);
    closeup.fov_y_deg = 45.0;
    closeup.width = 480;
    closeup.height = 320;
    Write(out_dir + "/render_cut_closeup.png", ToBgr(renderer->Render(scene, {closeup}).cameras[0]));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "bench_render_frames: %s\n", error.what());
    return 1;
  }
  return 0;
}
