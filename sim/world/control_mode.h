// The control modes: ManiSkill's, meaning exactly what they mean for ManiSkill3's panda_stick (a
// Panda without a gripper: 7 arm joints, actions without a gripper dimension), plus the paper's
// quaternion end-effector pose under its own name. "Root frame" is the robot base frame.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/world/model.h"

namespace culinarycut {

enum class ControlMode {
  kJointPosition,             // pd_joint_pos: 7 joint targets (rad), not normalised
  kJointDeltaPosition,        // pd_joint_delta_pos: 7 normalised deltas in [-1, 1] -> +-0.1 rad on the measured qpos
  kEndEffectorDeltaPosition,  // pd_ee_delta_pos: [dx, dy, dz] in [-1, 1] -> +-0.1 m (root frame); orientation held
  kEndEffectorDeltaPose,      // pd_ee_delta_pose: position as pd_ee_delta_pos, rotation [rx, ry, rz] clipped to the
                              // unit ball -> * 0.1 rad, XYZ Euler, applied in the root frame about the TCP
  kEndEffectorPose,           // pd_ee_pose: TCP [x, y, z] (m) and XYZ Euler [rx, ry, rz] (rad), root frame
  kEndEffectorPoseQuat,       // pd_ee_pose_quat (the paper's): TCP [x, y, z, qw, qx, qy, qz] in the world frame
};

// What [-1, 1] in a normalised mode means (ManiSkill3 panda_stick's controller configs).
inline constexpr double kDeltaJointScaleRad = 0.1;
inline constexpr double kDeltaPositionScaleM = 0.1;
inline constexpr double kDeltaRotationScaleRad = 0.1;

// What an action with no control mode means (ManiSkill's usual choice for teleoperation and VLAs).
inline constexpr ControlMode kDefaultControlMode = ControlMode::kEndEffectorDeltaPose;

const std::vector<ControlMode>& AllControlModes();
const char* ControlModeName(ControlMode mode);
std::optional<ControlMode> ParseControlMode(const std::string& name);

struct ActionBounds {
  std::vector<double> low;
  std::vector<double> high;
  std::string description;   // units and frame of each element
};

ActionBounds ActionBoundsFor(const Model& model, ControlMode mode);

}  // namespace culinarycut
