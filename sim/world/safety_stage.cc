#include "sim/world/safety_stage.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "sim/robot/kinematics.h"

namespace culinarycut {
namespace {

constexpr int kEdgeSamples = 5;  // points along the edge checked against each food's box

Eigen::Isometry3d TcpInWorld(const Model& model, JointValues q_rad) {
  return model.robot_base_in_world * TipPose(model.robot, q_rad, model.tcp_in_last_link);
}

// Distance (m) from a world point to an object's box at rest (0 inside).
double DistanceToBox(const task::ObjectBox& box, const Eigen::Vector3d& point_m) {
  const Eigen::Vector3d local = box.pose.inverse() * point_m;
  return (local.cwiseAbs() - 0.5 * box.extent_m).cwiseMax(0.0).norm();
}

// Distance (m) from the blade's edge (the TCP frame's x axis over the blade's length) to the box.
double EdgeDistance(const task::ObjectBox& box, const Eigen::Isometry3d& tcp, double blade_length_m) {
  double nearest_m = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kEdgeSamples; ++i) {
    const double along_m = blade_length_m * (static_cast<double>(i) / (kEdgeSamples - 1) - 0.5);
    nearest_m = std::min(nearest_m, DistanceToBox(box, tcp * Eigen::Vector3d(along_m, 0.0, 0.0)));
  }
  return nearest_m;
}

// The food's extent along the blade (m): the length of edge that will be in it, at most the blade's.
double ExtentAlongBlade(const task::ObjectBox& box, const Eigen::Vector3d& blade_direction, double blade_length_m) {
  double extent_m = 0.0;
  for (int k = 0; k < 3; ++k) extent_m += box.extent_m[k] * std::abs(box.pose.linear().col(k).dot(blade_direction));
  return std::min(extent_m, blade_length_m);
}

safety::CutMaterial CutMaterialOf(const mpm::Material& material, double edge_length_m) {
  return safety::CutMaterial{material.youngs_modulus_pa * 1e-6, material.yield_stress_pa * 1e-3,
                             material.fracture_toughness_j_m2, edge_length_m};
}

}  // namespace

safety::LimiterReport LimitJointTarget(const Model& model, State* state) {
  const safety::LimiterModel& limiter = *model.limiter;
  const FoodModel& food = *model.food;
  const Eigen::VectorXd q = state->physics->JointPositions();
  const Eigen::VectorXd step = state->q_target_rad - q;
  const Eigen::Isometry3d tcp_now = TcpInWorld(model, q);
  const Eigen::Vector3d cutting_direction = tcp_now.linear().col(2);  // the edge leads: the TCP's +z
  const auto tcp_at = [&](double s) { return TcpInWorld(model, q + s * step); };

  // Entering a food: the edge near its box now, half-way or at the target, so a fast step that would
  // jump into the food from outside the approach distance is caught too.
  const Eigen::Isometry3d swept[3] = {tcp_now, tcp_at(0.5), tcp_at(1.0)};
  safety::LimiterInputs inputs;
  const double blade_length_m = food.knife.blade_length_m;
  for (std::size_t i = 0; i < food.objects.size(); ++i) {
    const task::ObjectBox& box = food.objects[i];
    double distance_m = std::numeric_limits<double>::infinity();
    for (const Eigen::Isometry3d& tcp : swept) distance_m = std::min(distance_m, EdgeDistance(box, tcp, blade_length_m));
    if (distance_m > limiter.settings.approach_distance_m) continue;
    const double edge_length_m = ExtentAlongBlade(box, tcp_now.linear().col(0), blade_length_m);
    inputs.foods_near_edge.push_back(CutMaterialOf(food.solver->materials[i], edge_length_m));
  }
  const double cos_tilt = std::clamp(cutting_direction.dot(-Eigen::Vector3d::UnitZ()), -1.0, 1.0);
  inputs.blade_tilt_deg = std::acos(cos_tilt) * 180.0 / M_PI;
  inputs.knife_force_n = std::max(state->food->wrench.force_n.norm(), state->food->control_step_wrench.force_n.norm());
  const safety::IntoFoodLimit limit = safety::LimitIntoFood(limiter.settings, *limiter.force_model, inputs);

  safety::LimiterReport report;
  report.v_safe_m_s = limit.v_safe_m_s;
  report.predicted_force_n = limit.predicted_force_n;
  report.out_of_range = limit.out_of_range;
  state->safety.v_safe_m_s = limit.v_safe_m_s;
  state->safety.predicted_force_n = limit.predicted_force_n;
  state->safety.out_of_range = limit.out_of_range;

  // The knife's motion into the food (m) if the joints went s of the way to the target.
  const auto into_food_m = [&](double s) {
    return (tcp_at(s).translation() - tcp_now.translation()).dot(cutting_direction);
  };
  // The PD servo moves fastest at the step's start, at k times the distance left (qdot = k (q_target - q)):
  // a speed cap v on the knife is a cap of v / k on the target's distance into the food.
  const double stiffness_per_s = model.config.robot.joint_stiffness_per_s;
  const double commanded_m = into_food_m(1.0);
  report.commanded_speed_m_s = std::max(0.0, stiffness_per_s * commanded_m);
  const double speed_cap_m = limit.max_speed_m_s / stiffness_per_s;  // infinite when the speed guard is idle
  const double cap_m = limit.holds() ? std::min(kHoldToleranceM, speed_cap_m) : speed_cap_m;
  if (!(commanded_m > cap_m)) return report;

  report.target_scale = safety::LargestScaleWithin(into_food_m, cap_m);
  state->q_target_rad = q + report.target_scale * step;
  report.acted = true;
  std::ostringstream reason;
  reason << limit.hold_reason;
  for (safety::Guard guard : {safety::Guard::kForce, safety::Guard::kEntryAngle}) {
    report.guard_counts[static_cast<int>(guard)] = limit.holding[static_cast<int>(guard)] ? 1 : 0;
  }
  if (commanded_m > speed_cap_m) {
    report.guard_counts[static_cast<int>(safety::Guard::kSpeed)] = 1;
    if (reason.tellp() > 0) reason << "; ";
    reason << "commanded " << report.commanded_speed_m_s << " m/s into the food, above v_safe (1 - margin) = "
           << limit.max_speed_m_s << " m/s";
  }
  report.reason = reason.str();
  for (int i = 0; i < safety::kGuardCount; ++i) state->safety.interventions[i] += report.guard_counts[i];
  return report;
}

}  // namespace culinarycut
