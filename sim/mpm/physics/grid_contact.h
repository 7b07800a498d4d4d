// Contact of a grid node with a rigid collider: non-penetration and Coulomb friction.
#pragma once

#include <Eigen/Core>

namespace culinarycut::mpm {

// Non-penetration and Coulomb friction of a node velocity against a collider moving at
// `collider_velocity` with outward normal `normal` (paper: "decomposing relative velocity into
// normal/tangential components"). Returns whether the node was approaching (and was changed).
inline bool ResolveContact(const Eigen::Vector3d& normal, const Eigen::Vector3d& collider_velocity,
                           double friction, bool use_friction, Eigen::Vector3d* velocity,
                           double* approach_speed) {
  const Eigen::Vector3d relative = *velocity - collider_velocity;
  const double normal_speed = relative.dot(normal);
  if (normal_speed >= 0.0) return false;
  *approach_speed = -normal_speed;
  Eigen::Vector3d tangential = relative - normal_speed * normal;
  if (use_friction) {
    const double slip = tangential.norm();
    // Static friction holds the node when the tangential speed is within mu |v_n|.
    if (slip <= -friction * normal_speed) {
      tangential.setZero();
    } else {
      tangential *= 1.0 + friction * normal_speed / slip;
    }
  }
  *velocity = collider_velocity + tangential;
  return true;
}

}  // namespace culinarycut::mpm
