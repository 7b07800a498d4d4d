#include "sim/core/pose.h"

#include <algorithm>
#include <cmath>

#include <cmath>

namespace culinarycut {

Vector7d PoseToVector(const Eigen::Isometry3d& pose) {
  Eigen::Quaterniond q(pose.rotation());
  // Keep w >= 0 so equal rotations give equal vectors.
  if (q.w() < 0) q.coeffs() *= -1.0;
  Vector7d out;
  out << pose.translation(), q.w(), q.x(), q.y(), q.z();
  return out;
}

Eigen::Isometry3d PoseFromVector(const Vector7d& pose) {
  Eigen::Quaterniond q(pose[3], pose[4], pose[5], pose[6]);
  q.normalize();
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = q.toRotationMatrix();
  out.translation() = pose.head<3>();
  return out;
}

std::optional<Eigen::Vector4d> NormalizedQuaternion(const Eigen::Vector4d& wxyz) {
  const double largest = wxyz.cwiseAbs().maxCoeff();
  if (!std::isfinite(largest) || largest == 0.0) return std::nullopt;
  return (wxyz / largest).normalized();
}

Eigen::Vector3d OrientationError(const Eigen::Matrix3d& from, const Eigen::Matrix3d& to) {
  const Eigen::AngleAxisd delta(to * from.transpose());
  return delta.axis() * delta.angle();
}

Eigen::Matrix3d RotationFromAxisAngle(const Eigen::Vector3d& axis_angle) {
  const double angle = axis_angle.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, axis_angle / angle).toRotationMatrix();
}

Eigen::Matrix3d RotationFromEulerXyz(const Eigen::Vector3d& angles_rad) {
  return (Eigen::AngleAxisd(angles_rad.x(), Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(angles_rad.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(angles_rad.z(), Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

Eigen::Vector3d EulerXyzFromRotation(const Eigen::Matrix3d& r) {
  // R = Rx(a) Ry(b) Rz(c): R02 = sin b, R12 = -sin a cos b, R22 = cos a cos b, R01 = -cos b sin c, R00 = cos b cos c.
  return Eigen::Vector3d(std::atan2(-r(1, 2), r(2, 2)), std::asin(std::clamp(r(0, 2), -1.0, 1.0)),
                         std::atan2(-r(0, 1), r(0, 0)));
}

double AngleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

}  // namespace culinarycut
