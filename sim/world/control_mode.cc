#include "sim/world/control_mode.h"

#include <cmath>
#include <limits>

namespace culinarycut {
namespace {

// TCP targets outside this box (m, world) are clipped: it encloses the Panda's reach on the table.
constexpr double kWorkspaceLowM[3] = {-0.9, -0.9, -0.05};
constexpr double kWorkspaceHighM[3] = {0.9, 0.9, 1.2};
constexpr double kUnbounded = std::numeric_limits<double>::infinity();

}  // namespace

const std::vector<ControlMode>& AllControlModes() {
  static const std::vector<ControlMode> modes = {
      ControlMode::kJointPosition,         ControlMode::kJointDeltaPosition, ControlMode::kEndEffectorDeltaPosition,
      ControlMode::kEndEffectorDeltaPose,  ControlMode::kEndEffectorPose,    ControlMode::kEndEffectorPoseQuat};
  return modes;
}

const char* ControlModeName(ControlMode mode) {
  switch (mode) {
    case ControlMode::kJointPosition: return "pd_joint_pos";
    case ControlMode::kJointDeltaPosition: return "pd_joint_delta_pos";
    case ControlMode::kEndEffectorDeltaPosition: return "pd_ee_delta_pos";
    case ControlMode::kEndEffectorDeltaPose: return "pd_ee_delta_pose";
    case ControlMode::kEndEffectorPose: return "pd_ee_pose";
    case ControlMode::kEndEffectorPoseQuat: return "pd_ee_pose_quat";
  }
  return "unknown";
}

std::optional<ControlMode> ParseControlMode(const std::string& name) {
  for (ControlMode mode : AllControlModes()) {
    if (name == ControlModeName(mode)) return mode;
  }
  return std::nullopt;
}

ActionBounds ActionBoundsFor(const Model& model, ControlMode mode) {
  ActionBounds bounds;
  const int dof = model.robot.dof();
  switch (mode) {
    case ControlMode::kJointPosition:
      for (const JointLimits& limits : model.robot.limits) {
        bounds.low.push_back(limits.lower_rad);
        bounds.high.push_back(limits.upper_rad);
      }
      bounds.description = "joint position targets q1..q7 (rad)";
      break;
    case ControlMode::kJointDeltaPosition:
      bounds.low.assign(dof, -1.0);
      bounds.high.assign(dof, 1.0);
      bounds.description = "normalised joint deltas in [-1, 1]: x 0.1 rad, added to the measured qpos";
      break;
    case ControlMode::kEndEffectorDeltaPosition:
      bounds.low.assign(3, -1.0);
      bounds.high.assign(3, 1.0);
      bounds.description = "normalised knife TCP delta [dx, dy, dz] in [-1, 1]: x 0.1 m in the root frame; "
                           "orientation held";
      break;
    case ControlMode::kEndEffectorDeltaPose:
      bounds.low.assign(6, -1.0);
      bounds.high.assign(6, 1.0);
      bounds.description =
          "normalised knife TCP delta: [dx, dy, dz] in [-1, 1] x 0.1 m (root frame), [rx, ry, rz] clipped to the unit "
          "ball x 0.1 rad (XYZ Euler, applied in the root frame about the TCP), from the measured TCP pose";
      break;
    case ControlMode::kEndEffectorPose:
      // Angles unbounded, as ManiSkill's (any angle names a rotation); positions kept in the workspace.
      bounds.low = {kWorkspaceLowM[0], kWorkspaceLowM[1], kWorkspaceLowM[2], -kUnbounded, -kUnbounded, -kUnbounded};
      bounds.high = {kWorkspaceHighM[0], kWorkspaceHighM[1], kWorkspaceHighM[2], kUnbounded, kUnbounded, kUnbounded};
      bounds.description = "knife TCP target [x, y, z] (m) and XYZ Euler angles [rx, ry, rz] (rad), root frame";
      break;
    case ControlMode::kEndEffectorPoseQuat:
      bounds.low = {kWorkspaceLowM[0], kWorkspaceLowM[1], kWorkspaceLowM[2], -1, -1, -1, -1};
      bounds.high = {kWorkspaceHighM[0], kWorkspaceHighM[1], kWorkspaceHighM[2], 1, 1, 1, 1};
      bounds.description = "knife TCP target [x, y, z] (m, world) and quaternion [qw, qx, qy, qz] (normalised)";
      break;
  }
  return bounds;
}

}  // namespace culinarycut
