// ManiSkill's control modes and the shape and bounds of their actions.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/world/model.h"

namespace culinarycut {

enum class ControlMode {
  kJointPosition,          // pd_joint_pos: 7 joint targets (rad)
  kJointDeltaPosition,     // pd_joint_delta_pos: 7 deltas (rad) on the measured qpos
  kEndEffectorPose,        // pd_ee_pose: TCP [x, y, z, qw, qx, qy, qz] in the world frame
  kEndEffectorDeltaPose,   // pd_ee_delta_pose: [dx, dy, dz] (m, world) + axis-angle [rx, ry, rz] (rad, world-aligned, about the TCP)
};

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
