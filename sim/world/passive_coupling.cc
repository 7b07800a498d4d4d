#include "sim/world/passive_coupling.h"

#include <algorithm>

namespace culinarycut {

Eigen::Vector3d PassiveCouplingForce(const Eigen::Vector3d& food_force_n, const Eigen::Matrix3d& knife_axes,
                                     const Eigen::Vector3d& tcp_velocity_m_s, double timestep_s,
                                     const Eigen::Vector3d& absorbed_j) {
  Eigen::Vector3d force = knife_axes.transpose() * food_force_n;
  const Eigen::Vector3d velocity = knife_axes.transpose() * tcp_velocity_m_s;
  for (int axis = 0; axis < 3; ++axis) {
    const double power_w = force[axis] * velocity[axis];  // the food working on the arm when > 0
    const double allowed_w = std::max(0.0, absorbed_j[axis]) / timestep_s;
    if (power_w > allowed_w) force[axis] *= allowed_w / power_w;
  }
  return knife_axes * force;
}

void BookCouplingWork(const Eigen::Vector3d& applied_force_n, const Eigen::Matrix3d& knife_axes,
                      const Eigen::Vector3d& tcp_displacement_m, Eigen::Vector3d* absorbed_j) {
  const Eigen::Vector3d force = knife_axes.transpose() * applied_force_n;
  const Eigen::Vector3d displacement = knife_axes.transpose() * tcp_displacement_m;
  *absorbed_j -= force.cwiseProduct(displacement);
}

}  // namespace culinarycut
