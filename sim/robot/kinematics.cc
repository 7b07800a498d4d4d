#include "sim/robot/kinematics.h"

namespace culinarycut {

Eigen::Isometry3d ForwardKinematics(const RobotDescription& robot, const Eigen::VectorXd& q_rad,
                                    std::vector<Eigen::Isometry3d>* link_poses) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (link_poses) link_poses->resize(robot.dof());
  for (int i = 0; i < robot.dof(); ++i) {
    pose = pose * robot.joint_origins[i] * Eigen::AngleAxisd(q_rad[i], robot.joint_axes[i]);
    if (link_poses) (*link_poses)[i] = pose;
  }
  return pose;
}

Eigen::Isometry3d TipPose(const RobotDescription& robot, const Eigen::VectorXd& q_rad,
                          const Eigen::Isometry3d& tip_in_last_link) {
  return ForwardKinematics(robot, q_rad) * tip_in_last_link;
}

Jacobian TipJacobian(const RobotDescription& robot, const Eigen::VectorXd& q_rad,
                     const Eigen::Isometry3d& tip_in_last_link) {
  std::vector<Eigen::Isometry3d> link_poses;
  const Eigen::Vector3d tip = (ForwardKinematics(robot, q_rad, &link_poses) * tip_in_last_link).translation();
  Jacobian jacobian(6, robot.dof());
  for (int i = 0; i < robot.dof(); ++i) {
    // Revolute joint: the axis in the base frame and the lever arm to the tip.
    const Eigen::Vector3d axis = link_poses[i].linear() * robot.joint_axes[i];
    jacobian.block<3, 1>(0, i) = axis.cross(tip - link_poses[i].translation());
    jacobian.block<3, 1>(3, i) = axis;
  }
  return jacobian;
}

Eigen::VectorXd GravityTorques(const RobotDescription& robot, const Eigen::VectorXd& q_rad,
                               const Eigen::Vector3d& gravity_m_s2) {
  std::vector<Eigen::Isometry3d> link_poses;
  ForwardKinematics(robot, q_rad, &link_poses);
  Eigen::VectorXd torques = Eigen::VectorXd::Zero(robot.dof());
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
