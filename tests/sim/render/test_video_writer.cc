#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include <catch2/catch.hpp>
#include <opencv2/videoio.hpp>

#include "sim/render/render_error.h"
#include "sim/render/video_writer.h"
#include "tests/sim/render/render_test_scenes.h"

namespace culinarycut::render {
namespace {

TEST_CASE("An episode video of three tiled cameras is written and reads back frame by frame") {
  const std::string path =
      (std::filesystem::temp_directory_path() / ("culinarycut_render_test_" + std::to_string(::getpid()) + ".mp4")).string();
  RenderScene scene;
  const auto cameras = DefaultCameras(scene.layout, 64, 48);
  VideoWriter writer;
  writer.Open(path, 10.0, {{"front", "left", "right"}, 0, 64, 48});
  CHECK(writer.width() == 192);
  CHECK(writer.height() == 48);
  for (int frame = 0; frame < 6; ++frame) {
    Eigen::VectorXd q = testing::ReadyPose();
    q[0] = 0.05 * frame;
    scene.link_poses_world = testing::PandaLinkPoses(q);
    writer.Add(testing::SharedRenderer().Render(scene, cameras).cameras);
  }
  CHECK(writer.frames_written() == 6);
  writer.Close();

  cv::VideoCapture capture(path);
  REQUIRE(capture.isOpened());
  int frames = 0;
  cv::Mat image;
  while (capture.read(image)) {
    CHECK(image.cols == 192);
    CHECK(image.rows == 48);
    ++frames;
  }
  CHECK(frames == 6);
  std::filesystem::remove(path);
}

TEST_CASE("The video writer names the path it cannot open and the camera it misses") {
  VideoWriter writer;
  CHECK_THROWS_WITH(writer.Open("/nonexistent/folder/episode.mp4", 10.0, {{"front"}, 0, 64, 48}),
                    Catch::Contains("/nonexistent/folder/episode.mp4"));
  const std::string path = (std::filesystem::temp_directory_path() / "culinarycut_render_test_missing.mp4").string();
  writer.Open(path, 10.0, {{"wrist"}, 0, 64, 48});
  CameraImages front;
  front.name = "front";
  CHECK_THROWS_WITH(writer.Add({front}), Catch::Contains("wrist"));
  writer.Close();
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace culinarycut::render
