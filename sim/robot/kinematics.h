// Forward kinematics and the geometric Jacobian of a RobotDescription, in the robot base frame.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sim/robot/robot_description.h"

namespace culinarycut {

// Joint-space vectors and Jacobians with their storage inside the object (at most kMaxJoints
// joints), so the physics loop that makes them per substep never touches the heap.
inline constexpr int kMaxJoints = 16;
using JointVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxJoints, 1>;
// Any contiguous joint vector (VectorXd or JointVector), read without a copy.
using JointValues = Eigen::Ref<const Eigen::VectorXd>;
// Rows: linear (m/rad), angular (rad/rad); one column per joint.
using Jacobian = Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::ColMajor, 6, kMaxJoints>;

// Pose of every movable link frame in the base frame; returns links[dof-1]'s pose.
Eigen::Isometry3d ForwardKinematics(const RobotDescription& robot, JointValues q_rad,
                                    std::vector<Eigen::Isometry3d>* link_poses = nullptr);

// Pose of a frame fixed to the last link (`tip_in_last_link`) in the base frame.
Eigen::Isometry3d TipPose(const RobotDescription& robot, JointValues q_rad,
                          const Eigen::Isometry3d& tip_in_last_link);

// 6 x dof Jacobian of the tip point and frame, both expressed in the base frame.
Jacobian TipJacobian(const RobotDescription& robot, JointValues q_rad,
                     const Eigen::Isometry3d& tip_in_last_link);

// Joint torques (N m) that hold the arm still against gravity (m/s^2, base frame):
// tau = -sum_j J_com_j^T m_j g over the links the joint carries.
JointVector GravityTorques(const RobotDescription& robot, JointValues q_rad,
                               const Eigen::Vector3d& gravity_m_s2);

}  // namespace culinarycut
