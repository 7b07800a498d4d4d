#include "sim/robot/inverse_kinematics.h"

#include <algorithm>
#include <vector>

#include "sim/core/pose.h"
#include "sim/robot/kinematics.h"

namespace culinarycut {

Eigen::VectorXd ClampToJointLimits(const RobotDescription& robot, Eigen::VectorXd q_rad, double margin_rad) {
  for (int i = 0; i < robot.dof(); ++i) {
    q_rad[i] = std::clamp(q_rad[i], robot.limits[i].lower_rad + margin_rad, robot.limits[i].upper_rad - margin_rad);
  }
  return q_rad;
}

namespace {

// One damped-least-squares step. Joints at a limit that the step would push further are frozen
// (their Jacobian column removed) and the step is solved again, so the free joints do the work
// instead of the solver stalling against the limit.
Eigen::VectorXd LimitAwareStep(const RobotDescription& robot, const Eigen::MatrixXd& jacobian,
                               const Eigen::Matrix<double, 6, 1>& error, const Eigen::VectorXd& q,
                               double lambda_squared, double margin_rad) {
  const int dof = robot.dof();
  std::vector<bool> frozen(dof, false);
  Eigen::VectorXd step = Eigen::VectorXd::Zero(dof);
  for (int pass = 0; pass <= dof; ++pass) {
    Eigen::MatrixXd active = jacobian;
    for (int i = 0; i < dof; ++i) {
      if (frozen[i]) active.col(i).setZero();
    }
    step = active.transpose() *
           (active * active.transpose() + lambda_squared * Eigen::Matrix<double, 6, 6>::Identity()).ldlt().solve(error);
    bool changed = false;
    for (int i = 0; i < dof; ++i) {
      const bool at_lower = q[i] <= robot.limits[i].lower_rad + margin_rad + 1e-9 && step[i] < 0;
      const bool at_upper = q[i] >= robot.limits[i].upper_rad - margin_rad - 1e-9 && step[i] > 0;
      if (!frozen[i] && (at_lower || at_upper)) {
        frozen[i] = true;
        changed = true;
      }
    }
    if (!changed) break;
  }
  for (int i = 0; i < dof; ++i) {
    if (frozen[i]) step[i] = 0.0;
  }
  return step;
}

}  // namespace

IkResult SolveInverseKinematics(const RobotDescription& robot, const Eigen::Isometry3d& tip_in_last_link,
                                const Eigen::Isometry3d& target, const Eigen::VectorXd& q_seed_rad,
                                const IkOptions& options) {
  IkResult result;
  result.q_rad = ClampToJointLimits(robot, q_seed_rad, options.limit_margin_rad);
  // Orientation rows are scaled to metres so one damping value suits both.
  Eigen::Matrix<double, 6, 1> weights;
  weights << 1, 1, 1, options.orientation_weight_m, options.orientation_weight_m, options.orientation_weight_m;
  const double lambda_squared = options.damping * options.damping;

  for (result.iterations = 0; result.iterations <= options.max_iterations; ++result.iterations) {
    const Eigen::Isometry3d tip = TipPose(robot, result.q_rad, tip_in_last_link);
    Eigen::Matrix<double, 6, 1> error;
    error.head<3>() = target.translation() - tip.translation();
    error.tail<3>() = OrientationError(tip.linear(), target.linear());
    result.position_error_m = error.head<3>().norm();
    result.orientation_error_rad = error.tail<3>().norm();
    result.converged = result.position_error_m <= options.position_tolerance_m &&
                       result.orientation_error_rad <= options.orientation_tolerance_rad;
    if (result.converged || result.iterations == options.max_iterations) break;

    const Eigen::MatrixXd jacobian = weights.asDiagonal() * TipJacobian(robot, result.q_rad, tip_in_last_link);
    const Eigen::Matrix<double, 6, 1> weighted_error = weights.asDiagonal() * error;
    Eigen::VectorXd step =
        LimitAwareStep(robot, jacobian, weighted_error, result.q_rad, lambda_squared, options.limit_margin_rad);
    const double largest = step.cwiseAbs().maxCoeff();
    if (largest > options.max_joint_step_rad) step *= options.max_joint_step_rad / largest;
    result.q_rad = ClampToJointLimits(robot, result.q_rad + step, options.limit_margin_rad);
  }
  return result;
}

}  // namespace culinarycut
