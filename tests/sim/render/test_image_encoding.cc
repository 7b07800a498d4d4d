#include <catch2/catch.hpp>
#include <opencv2/imgcodecs.hpp>

#include "sim/render/image_encoding.h"
#include "sim/render/render_error.h"
#include "tests/sim/render/render_test_scenes.h"

namespace culinarycut::render {
namespace {

CameraImages RenderedFront() {
  RenderScene scene;
  scene.link_poses_world = testing::PandaLinkPoses(testing::ReadyPose());
  auto cameras = DefaultCameras(scene.layout, 120, 90);
  cameras[0].depth = true;
  return testing::SharedRenderer().Render(scene, {cameras[0]}).cameras.at(0);
}

TEST_CASE("PNG encoding round-trips the RGB image exactly; JPEG keeps size and colours") {
  const CameraImages images = RenderedFront();
  const std::vector<std::uint8_t> png = EncodeImage(images, "png");
  const cv::Mat decoded = cv::imdecode(png, cv::IMREAD_COLOR);  // BGR
  REQUIRE(decoded.cols == 120);
  REQUIRE(decoded.rows == 90);
  bool identical = true;
  for (int v = 0; v < 90; ++v) {
    for (int u = 0; u < 120; ++u) {
      const cv::Vec3b bgr = decoded.at<cv::Vec3b>(v, u);
      const std::size_t at = 3 * (static_cast<std::size_t>(v) * 120 + u);
      identical = identical && bgr[2] == images.rgb[at] && bgr[1] == images.rgb[at + 1] && bgr[0] == images.rgb[at + 2];
    }
  }
  CHECK(identical);

  const std::vector<std::uint8_t> jpg = EncodeImage(images, "jpg", 95);
  const cv::Mat lossy = cv::imdecode(jpg, cv::IMREAD_COLOR);
  CHECK(lossy.cols == 120);
  CHECK(lossy.rows == 90);
  CHECK(cv::norm(lossy, decoded, cv::NORM_L1) / (120.0 * 90 * 3) < 6.0);  // mean error per channel
  CHECK_THROWS_WITH(EncodeImage(images, "gif"), Catch::Contains("png or jpg"));
}

TEST_CASE("Depth encodes as a 16-bit millimetre PNG") {
  const CameraImages images = RenderedFront();
  const cv::Mat decoded = cv::imdecode(EncodeDepthPng16(images), cv::IMREAD_UNCHANGED);
  REQUIRE(decoded.type() == CV_16UC1);
  const int u = 60, v = 45;
  CHECK(decoded.at<std::uint16_t>(v, u) == Approx(images.depth_m[v * 120 + u] * 1000.0f).margin(0.5));
  CameraImages no_depth = images;
  no_depth.depth_m.clear();
  CHECK_THROWS_AS(EncodeDepthPng16(no_depth), RenderError);
}

}  // namespace
}  // namespace culinarycut::render
