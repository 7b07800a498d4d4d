#include <cmath>

#include <catch2/catch.hpp>

#include "sim/render/camera.h"
#include "sim/render/render_error.h"

namespace culinarycut::render {
namespace {

// The window pixel OpenGL rasterises a world point into, converted to OpenCV (u right, v down,
// pixel centres at integers).
Eigen::Vector2d ProjectOpenGl(const CameraIntrinsics& intrinsics, const CameraExtrinsics& extrinsics,
                              const Eigen::Vector3d& point_world) {
  const Eigen::Vector4d clip = intrinsics.gl_projection * extrinsics.gl_view * point_world.homogeneous();
  const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
  const double window_x = (ndc.x() + 1.0) * 0.5 * intrinsics.width;   // from the left edge
  const double window_y = (ndc.y() + 1.0) * 0.5 * intrinsics.height;  // from the bottom edge
  return {window_x - 0.5, intrinsics.height - window_y - 0.5};
}

TEST_CASE("Intrinsics follow the field of view and put the optical axis at the image centre") {
  CameraSpec camera;
  camera.width = 640;
  camera.height = 480;
  camera.fov_y_deg = 90.0;
  const CameraIntrinsics k = ComputeIntrinsics(camera);
  CHECK(k.K(0, 0) == Approx(240.0));  // tan(45 deg) = 1: f = H / 2
  CHECK(k.K(1, 1) == Approx(240.0));
  CHECK(k.K(0, 2) == Approx(319.5));
  CHECK(k.K(1, 2) == Approx(239.5));
}

TEST_CASE("A world point projects to the same pixel through OpenCV K[R|t] and the OpenGL matrices") {
  CameraSpec camera;
  camera.width = 320;
  camera.height = 200;
  camera.fov_y_deg = 50.0;
  const CameraIntrinsics k = ComputeIntrinsics(camera);
  const CameraExtrinsics e = ComputeExtrinsics(LookAt({1.2, 0.4, 0.8}, {0.5, 0.0, 0.05}));
  for (const Eigen::Vector3d& point : {Eigen::Vector3d(0.5, 0.0, 0.05), Eigen::Vector3d(0.6, 0.1, 0.2),
                                      Eigen::Vector3d(0.3, -0.2, 0.0), Eigen::Vector3d(0.9, 0.3, 0.5)}) {
    const Eigen::Vector2d cv = ProjectOpenCv(k, e, point);
    const Eigen::Vector2d gl = ProjectOpenGl(k, e, point);
    CHECK(cv.x() == Approx(gl.x()).margin(1e-6));
    CHECK(cv.y() == Approx(gl.y()).margin(1e-6));
  }
  // The look-at target is on the optical axis.
  const Eigen::Vector2d center = ProjectOpenCv(k, e, {0.5, 0.0, 0.05});
  CHECK(center.x() == Approx(159.5).margin(1e-9));
  CHECK(center.y() == Approx(99.5).margin(1e-9));
}

TEST_CASE("The GL view is the OpenCV world-to-camera turned by pi about x") {
  const Eigen::Isometry3d pose = LookAt({0.2, -0.7, 0.5}, {0.5, 0.0, 0.02});
  const CameraExtrinsics e = ComputeExtrinsics(pose);
  CHECK((e.world_to_camera * pose).matrix().isIdentity(1e-12));
  const Eigen::Vector3d p(0.4, 0.1, 0.3);
  const Eigen::Vector3d cv = e.world_to_camera * p;
  const Eigen::Vector4d gl = e.gl_view * p.homogeneous();
  CHECK(gl.x() == Approx(cv.x()));
  CHECK(gl.y() == Approx(-cv.y()));
  CHECK(gl.z() == Approx(-cv.z()));
}

TEST_CASE("LookAt keeps image up towards world up and z towards the target") {
  const Eigen::Isometry3d pose = LookAt({1.0, 0.0, 1.0}, {0.0, 0.0, 0.0});
  CHECK(pose.linear().col(2).isApprox(Eigen::Vector3d(-1, 0, -1).normalized()));
  CHECK(pose.linear().col(1).z() < 0.0);  // image y (down) points down in the world
  CHECK(std::abs(pose.linear().determinant() - 1.0) < 1e-12);
  // Straight down does not degenerate.
  const Eigen::Isometry3d down = LookAt({0.0, 0.0, 1.0}, {0.0, 0.0, 0.0});
  CHECK(std::abs(down.linear().determinant() - 1.0) < 1e-12);
}

TEST_CASE("The default cameras look at the board from the front, left and right") {
  const SceneLayout layout;
  const auto cameras = DefaultCameras(layout);
  REQUIRE(cameras.size() == 3);
  CHECK(cameras[0].name == "front");
  CHECK(cameras[1].name == "left");
  CHECK(cameras[2].name == "right");
  CHECK(cameras[0].pose_in_world.translation().x() > layout.board_center_m.x());
  CHECK(cameras[1].pose_in_world.translation().y() > 0.3);
  CHECK(cameras[2].pose_in_world.translation().y() < -0.3);
  for (const CameraSpec& camera : cameras) {
    const CameraIntrinsics k = ComputeIntrinsics(camera);
    const Eigen::Vector2d board = ProjectOpenCv(k, ComputeExtrinsics(camera.pose_in_world), layout.board_center_m);
    CHECK(board.x() > 0.25 * camera.width);
    CHECK(board.x() < 0.75 * camera.width);
    CHECK(board.y() > 0.25 * camera.height);
    CHECK(board.y() < camera.height);
  }
  const CameraSpec wrist = WristCamera();
  CHECK(wrist.attached_link == "panda_link8");
}

TEST_CASE("Bad camera specs are refused with the camera's name") {
  CameraSpec camera;
  camera.name = "broken";
  camera.width = 0;
  CHECK_THROWS_WITH(ComputeIntrinsics(camera), Catch::Contains("broken") && Catch::Contains("width"));
  camera.width = 10;
  camera.fov_y_deg = 180.0;
  CHECK_THROWS_AS(ComputeIntrinsics(camera), RenderError);
}

}  // namespace
}  // namespace culinarycut::render
