#include "sim/render/camera.h"

#include <cmath>
#include <limits>

#include "sim/render/render_error.h"

namespace culinarycut::render {
namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix4d CvToGlEye() {
  Eigen::Matrix4d flip = Eigen::Matrix4d::Identity();
  flip(1, 1) = -1.0;
  flip(2, 2) = -1.0;
  return flip;
}

}  // namespace

CameraIntrinsics ComputeIntrinsics(const CameraSpec& camera) {
  if (camera.width <= 0 || camera.height <= 0) {
    throw RenderError("camera '" + camera.name + "': width and height must be positive, got " +
                      std::to_string(camera.width) + " x " + std::to_string(camera.height));
  }
  if (!(camera.fov_y_deg > 0.0 && camera.fov_y_deg < 180.0)) {
    throw RenderError("camera '" + camera.name + "': fov_y_deg must be in (0, 180), got " +
                      std::to_string(camera.fov_y_deg));
  }
  if (!(camera.near_m > 0.0 && camera.far_m > camera.near_m)) {
    throw RenderError("camera '" + camera.name + "': need 0 < near_m < far_m");
  }
  CameraIntrinsics out;
  out.width = camera.width;
  out.height = camera.height;
  out.near_m = camera.near_m;
  out.far_m = camera.far_m;
  const double tan_half = std::tan(camera.fov_y_deg * kPi / 360.0);
  const double focal_px = 0.5 * camera.height / tan_half;
  out.K << focal_px, 0.0, 0.5 * (camera.width - 1), 0.0, focal_px, 0.5 * (camera.height - 1), 0.0, 0.0, 1.0;

  // Standard symmetric perspective (gluPerspective): depth in [-1, 1] between near and far.
  const double aspect = static_cast<double>(camera.width) / camera.height;
  const double n = camera.near_m, f = camera.far_m;
  out.gl_projection.setZero();
  out.gl_projection(0, 0) = 1.0 / (aspect * tan_half);
  out.gl_projection(1, 1) = 1.0 / tan_half;
  out.gl_projection(2, 2) = -(f + n) / (f - n);
  out.gl_projection(2, 3) = -2.0 * f * n / (f - n);
  out.gl_projection(3, 2) = -1.0;
  return out;
}

CameraExtrinsics ComputeExtrinsics(const Eigen::Isometry3d& camera_to_world) {
  CameraExtrinsics out;
  out.camera_to_world = camera_to_world;
  out.world_to_camera = camera_to_world.inverse();
  out.gl_view = CvToGlEye() * out.world_to_camera.matrix();
  return out;
}

Eigen::Isometry3d LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up) {
  const Eigen::Vector3d forward = (target - eye).normalized();
  Eigen::Vector3d right = forward.cross(up);
  if (right.norm() < 1e-9) right = forward.unitOrthogonal();  // looking straight along `up`
  right.normalize();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = right;
  pose.linear().col(1) = down;
  pose.linear().col(2) = forward;
  pose.translation() = eye;
  return pose;
}

std::vector<CameraSpec> DefaultCameras(const SceneLayout& layout, int width, int height) {
  const Eigen::Vector3d board_top = layout.board_center_m + Eigen::Vector3d(0, 0, 0.5 * layout.board_size_m.z());
  // Aim a little above the board so the food, the knife and the arm above it share the view.
  const Eigen::Vector3d target = board_top + Eigen::Vector3d(-0.05, 0.0, 0.08);
  struct View { const char* name; Eigen::Vector3d offset_m; };
  const View views[] = {{"front", {0.80, 0.0, 0.55}}, {"left", {0.35, 0.80, 0.55}}, {"right", {0.35, -0.80, 0.55}}};
  std::vector<CameraSpec> cameras;
  for (const View& view : views) {
    CameraSpec camera;
    camera.name = view.name;
    camera.pose_in_world = LookAt(board_top + view.offset_m, target);
    camera.fov_y_deg = 55.0;
    camera.width = width;
    camera.height = height;
    cameras.push_back(camera);
  }
  return cameras;
}

CameraSpec WristCamera(int width, int height) {
  CameraSpec camera;
  camera.name = "wrist";
  camera.attached_link = "panda_link8";
  // The knife handle frame in the flange frame (joint knife_mount of assets/panda/panda_knife.urdf).
  const Eigen::Isometry3d handle_in_flange =
      Eigen::Translation3d(0.0, 0.0, 0.1) * Eigen::AngleAxisd(-0.25 * kPi, Eigen::Vector3d::UnitZ());
  // Beside the handle, level with the flange, looking down the blade; image up points to the arm.
  camera.pose_in_world = handle_in_flange * LookAt(Eigen::Vector3d(-0.02, 0.09, -0.09), Eigen::Vector3d(0.16, 0.0, 0.03),
                                                   -Eigen::Vector3d::UnitZ());
  camera.fov_y_deg = 75.0;
  camera.width = width;
  camera.height = height;
  return camera;
}

Eigen::Vector2d ProjectOpenCv(const CameraIntrinsics& intrinsics, const CameraExtrinsics& extrinsics,
                              const Eigen::Vector3d& point_world) {
  const Eigen::Vector3d in_camera = extrinsics.world_to_camera * point_world;
  if (in_camera.z() <= 0.0) {
    return Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  const Eigen::Vector3d pixel = intrinsics.K * (in_camera / in_camera.z());
  return pixel.head<2>();
}

}  // namespace culinarycut::render
