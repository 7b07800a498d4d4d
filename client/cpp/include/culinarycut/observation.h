// What the server reports, as plain C++ structs in SI units (the C++ client's counterpart of the
// Python client's dicts): the robot, the wrist wrench, the food, the instruction and the camera
// images of one observation, and the result of a Step. Poses are [x, y, z, qw, qx, qy, qz], world.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "culinarycut/v1/simulator.pb.h"

namespace culinarycut::client {

// One camera's images. Only the channels the scene asked for are filled.
struct CameraImage {
  std::string name;
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;      // height x width x 3, row 0 at the top (raw encoding)
  std::string rgb_encoded;            // the PNG or JPEG bytes when the camera asked for that encoding
  std::string rgb_encoding;           // "raw", "png" or "jpeg"
  std::vector<float> depth_m;         // height x width, along the optical axis; 0 where nothing was hit
  std::vector<std::int32_t> segmentation;  // height x width ids (labels in Observation)
  std::array<double, 9> intrinsic_cv{};    // OpenCV K, row-major (pixels)
  std::array<double, 12> extrinsic_cv{};   // [R | t] world -> OpenCV camera, row-major
  std::array<double, 16> cam2world_gl{};   // OpenGL camera frame -> world, row-major
};

struct FoodPiece {
  std::uint32_t object = 0;     // the food object it came from
  std::uint32_t particles = 0;
  double volume_m3 = 0.0;
  std::array<double, 3> centroid_m{};
  std::array<double, 3> bounds_min_m{};
  std::array<double, 3> bounds_max_m{};
};

struct FoodObservation {
  bool knife_contact = false;   // the knife touched the food during the last step
  bool mpm_awake = false;       // MPM ran during the last step
  std::vector<FoodPiece> pieces;
};

struct Observation {
  std::uint64_t frame_id = 0;
  double sim_time = 0.0;                      // s
  std::vector<double> qpos, qvel, qpos_target;  // rad, rad/s, rad
  std::vector<double> tcp_pose, tcp_velocity, flange_pose;
  // The food's wrench on the knife at the flange, flange frame: [fx, fy, fz] (N), [tx, ty, tz] (N m).
  std::vector<double> wrist_wrench;
  std::string instruction;                    // the scene task's; empty without one
  std::optional<FoodObservation> food;        // scenes with food only
  std::vector<CameraImage> cameras;           // the scene's cameras, in the scene's order
  std::vector<v1::SegmentLabel> segmentation_labels;
};

struct StepResult {
  Observation observation;
  double reward = 0.0;           // ManiSkill's sparse reward: 1 while the scene's task is done
  bool success = false;          // the scene's task is done
  bool terminated = false;
  bool truncated = false;
  std::optional<v1::TaskScore> task_score;  // scenes with a task only
  v1::StepInfo info;
};

// Converts a wire observation (and its stamp) into the plain struct; raw RGB, depth and
// segmentation bytes are unpacked, PNG and JPEG are kept encoded (rgb_encoded).
Observation FromWire(const v1::FrameStamp& stamp, const v1::Observation& wire);

}  // namespace culinarycut::client
