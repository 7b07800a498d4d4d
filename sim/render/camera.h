// Cameras: what the scene spec asks for (pose, field of view, resolution, channels) and the
// matrices that describe them in both conventions.
//
// Frames. The camera frame is OpenCV's: x right, y down, z forward (out of the lens). The OpenGL
// eye frame is x right, y up, z backward; the two differ by a rotation of pi about x:
// gl_eye = diag(1, -1, -1) * cv_camera. Pixel (u, v) has u to the right, v down, row 0 at the top,
// and the centre of the top-left pixel at (0, 0), so the optical axis is at ((W-1)/2, (H-1)/2).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sim/core/scene_layout.h"

namespace culinarycut::render {

struct CameraSpec {
  std::string name;
  // Camera frame (OpenCV: x right, y down, z forward) in the world frame, or in the frame of
  // `attached_link` when that is set.
  Eigen::Isometry3d pose_in_world = Eigen::Isometry3d::Identity();
  double fov_y_deg = 55.0;  // vertical field of view; pixels are square
  int width = 224;
  int height = 224;
  bool rgb = true;
  bool depth = false;
  bool segmentation = false;
  std::string attached_link;  // "" = fixed in the world; else a URDF link name, e.g. "panda_link8"
  double near_m = 0.01;       // clipping planes of the OpenGL projection
  double far_m = 20.0;
};

struct CameraIntrinsics {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();  // OpenCV: [fx 0 cx; 0 fy cy; 0 0 1], pixels
  // OpenGL clip-from-eye projection for the same image (symmetric frustum, near/far in metres).
  Eigen::Matrix4d gl_projection = Eigen::Matrix4d::Identity();
  int width = 0;
  int height = 0;
  double near_m = 0.0;
  double far_m = 0.0;
};

struct CameraExtrinsics {
  // OpenCV: x_camera = world_to_camera * x_world, camera frame x right, y down, z forward.
  Eigen::Isometry3d world_to_camera = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d camera_to_world = Eigen::Isometry3d::Identity();  // the camera pose in the world
  // OpenGL view matrix: eye frame x right, y up, z backward = diag(1,-1,-1) * world_to_camera.
  Eigen::Matrix4d gl_view = Eigen::Matrix4d::Identity();
};

// Throws RenderError for a non-positive size, a field of view outside (0, 180) or bad clip planes.
CameraIntrinsics ComputeIntrinsics(const CameraSpec& camera);
// `camera_to_world` is the resolved pose (for attached cameras: link pose * spec pose).
CameraExtrinsics ComputeExtrinsics(const Eigen::Isometry3d& camera_to_world);

// An OpenCV camera pose at `eye` looking at `target`, image "up" as close to `up` as possible.
Eigen::Isometry3d LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
                         const Eigen::Vector3d& up = Eigen::Vector3d::UnitZ());

// The paper's three views of the board: "front" (from +x, facing the robot), "left" (from +y) and
// "right" (from -y), RGB only, 224 x 224 unless told otherwise.
std::vector<CameraSpec> DefaultCameras(const SceneLayout& layout, int width = 224, int height = 224);

// A camera on the flange (attached to panda_link8) looking past the knife handle at the blade.
CameraSpec WristCamera(int width = 224, int height = 224);

// The pixel (u, v) where a world point lands, through K [R | t]; NaNs for a point behind the camera.
Eigen::Vector2d ProjectOpenCv(const CameraIntrinsics& intrinsics, const CameraExtrinsics& extrinsics,
                              const Eigen::Vector3d& point_world);

}  // namespace culinarycut::render
