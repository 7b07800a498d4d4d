#include "sim/robot/kinematics.h"

#include <array>

namespace culinarycut {
namespace {

// Every movable link's pose in the base frame, in storage of fixed capacity (no heap).
using LinkPoses = std::array<Eigen::Isometry3d, kMaxJoints>;

Eigen::Isometry3d LinkPosesInBase(const RobotDescription& robot, JointValues q_rad, LinkPoses* link_poses) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (int i = 0; i < robot.dof(); ++i) {
    pose = pose * robot.joint_origins[i] * Eigen::AngleAxisd(q_rad[i], robot.joint_axes[i]);
    (*link_poses)[i] = pose;
  }
  return pose;
}

}  // namespace

Eigen::Isometry3d ForwardKinematics(const RobotDescription& robot, JointValues q_rad,
                                    std::vector<Eigen::Isometry3d>* link_poses) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (link_poses) link_poses->resize(robot.dof());
  for (int i = 0; i < robot.dof(); ++i) {
    pose = pose * robot.joint_origins[i] * Eigen::AngleAxisd(q_rad[i], robot.joint_axes[i]);
    if (link_poses) (*link_poses)[i] = pose;
  }
  return pose;
}

Eigen::Isometry3d TipPose(const RobotDescription& robot, JointValues q_rad,
                          const Eigen::Isometry3d& tip_in_last_link) {
  return ForwardKinematics(robot, q_rad) * tip_in_last_link;
}

Jacobian TipJacobian(const RobotDescription& robot, JointValues q_rad,
                     const Eigen::Isometry3d& tip_in_last_link) {
  LinkPoses link_poses;
  const Eigen::Vector3d tip = (LinkPosesInBase(robot, q_rad, &link_poses) * tip_in_last_link).translation();
  Jacobian jacobian(6, robot.dof());
  for (int i = 0; i < robot.dof(); ++i) {
    // Revolute joint: the axis in the base frame and the lever arm to the tip.
    const Eigen::Vector3d axis = link_poses[i].linear() * robot.joint_axes[i];
    jacobian.block<3, 1>(0, i) = axis.cross(tip - link_poses[i].translation());
    jacobian.block<3, 1>(3, i) = axis;
  }
  return jacobian;
}

JointVector GravityTorques(const RobotDescription& robot, JointValues q_rad, const Eigen::Vector3d& gravity_m_s2) {
  LinkPoses link_poses;
  LinkPosesInBase(robot, q_rad, &link_poses);
  JointVector torques = JointVector::Zero(robot.dof());
  for (int j = 0; j < robot.dof(); ++j) {
    const Eigen::Vector3d com = link_poses[j] * robot.links[j].center_of_mass_m;
    const Eigen::Vector3d weight = robot.links[j].mass_kg * gravity_m_s2;
    // Link j's weight loads every joint from the base up to j.
    for (int i = 0; i <= j; ++i) {
      const Eigen::Vector3d axis = link_poses[i].linear() * robot.joint_axes[i];
      torques[i] -= axis.cross(com - link_poses[i].translation()).dot(weight);
    }
  }
  return torques;
}

}  // namespace culinarycut
