#include "sim/world/control_mode.h"

namespace culinarycut {
namespace {

constexpr double kMaxDeltaJointRad = 0.1;       // per control step, as ManiSkill
constexpr double kMaxDeltaPositionM = 0.1;      // per control step
constexpr double kMaxDeltaRotationRad = 0.1;    // per control step
// TCP targets outside this box (m, world) are clipped: it encloses the Panda's reach on the table.
constexpr double kWorkspaceLowM[3] = {-0.9, -0.9, -0.05};
constexpr double kWorkspaceHighM[3] = {0.9, 0.9, 1.2};

}  // namespace

const std::vector<ControlMode>& AllControlModes() {
  static const std::vector<ControlMode> modes = {ControlMode::kJointPosition, ControlMode::kJointDeltaPosition,
                                                 ControlMode::kEndEffectorPose, ControlMode::kEndEffectorDeltaPose};
  return modes;
}

const char* ControlModeName(ControlMode mode) {
  switch (mode) {
    case ControlMode::kJointPosition: return "pd_joint_pos";
    case ControlMode::kJointDeltaPosition: return "pd_joint_delta_pos";
    case ControlMode::kEndEffectorPose: return "pd_ee_pose";
    case ControlMode::kEndEffectorDeltaPose: return "pd_ee_delta_pose";
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
      bounds.low.assign(dof, -kMaxDeltaJointRad);
      bounds.high.assign(dof, kMaxDeltaJointRad);
      bounds.description = "joint position deltas dq1..dq7 (rad), added to the measured qpos";
      break;
    case ControlMode::kEndEffectorPose:
      bounds.low = {kWorkspaceLowM[0], kWorkspaceLowM[1], kWorkspaceLowM[2], -1, -1, -1, -1};
      bounds.high = {kWorkspaceHighM[0], kWorkspaceHighM[1], kWorkspaceHighM[2], 1, 1, 1, 1};
      bounds.description = "knife TCP target [x, y, z] (m, world) and quaternion [qw, qx, qy, qz] (normalised)";
      break;
    case ControlMode::kEndEffectorDeltaPose:
      bounds.low = {-kMaxDeltaPositionM, -kMaxDeltaPositionM, -kMaxDeltaPositionM,
                    -kMaxDeltaRotationRad, -kMaxDeltaRotationRad, -kMaxDeltaRotationRad};
      bounds.high = {kMaxDeltaPositionM, kMaxDeltaPositionM, kMaxDeltaPositionM,
                     kMaxDeltaRotationRad, kMaxDeltaRotationRad, kMaxDeltaRotationRad};
      bounds.description =
          "knife TCP delta [dx, dy, dz] (m, world frame) and axis-angle [rx, ry, rz] (rad, world-aligned, about the TCP), "
          "relative to the measured TCP pose";
      break;
  }
  return bounds;
}

}  // namespace culinarycut
