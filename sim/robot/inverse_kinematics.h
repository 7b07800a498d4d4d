// Differential inverse kinematics by damped least squares (Levenberg-Marquardt style), clamped
// to the joint limits at every iteration so a solution never leaves them.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sim/robot/robot_description.h"

namespace culinarycut {

struct IkOptions {
  int max_iterations = 100;
  double damping = 0.02;                      // lambda in (J J^T + lambda^2 I)^-1, (m)
  double position_tolerance_m = 1e-5;
  double orientation_tolerance_rad = 1e-4;
  double max_joint_step_rad = 0.2;            // per iteration, keeps large errors from overshooting
  double limit_margin_rad = 1e-3;             // solutions stay this far inside the joint limits
  double orientation_weight_m = 0.2;          // metres of position error worth one radian of rotation
};

struct IkResult {
  Eigen::VectorXd q_rad;
  bool converged = false;
  double position_error_m = 0.0;
  double orientation_error_rad = 0.0;
  int iterations = 0;
};

// Solves for joint angles that put `tip_in_last_link` at `target` (base frame), starting from q_seed.
IkResult SolveInverseKinematics(const RobotDescription& robot, const Eigen::Isometry3d& tip_in_last_link,
                                const Eigen::Isometry3d& target, const Eigen::VectorXd& q_seed_rad,
                                const IkOptions& options = {});

// Clamps joint angles to [lower + margin, upper - margin].
Eigen::VectorXd ClampToJointLimits(const RobotDescription& robot, Eigen::VectorXd q_rad, double margin_rad);

}  // namespace culinarycut
