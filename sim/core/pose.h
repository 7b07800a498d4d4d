// Rigid-pose helpers. Quaternions are stored (w, x, y, z) on the wire and in 7-vectors
// [x, y, z, qw, qx, qy, qz]; positions in metres, angles in radians.
#pragma once

#include <optional>

#include <Eigen/Geometry>

namespace culinarycut {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Vector7d = Eigen::Matrix<double, 7, 1>;

// [x, y, z, qw, qx, qy, qz] from an isometry.
Vector7d PoseToVector(const Eigen::Isometry3d& pose);

// Isometry from [x, y, z, qw, qx, qy, qz]; the quaternion is normalised (caller checks norm > 0).
Eigen::Isometry3d PoseFromVector(const Vector7d& pose);

// Unit quaternion (w, x, y, z) from one of any finite, positive norm: scaled by its largest element
// first, so 1e200 or 1e-200 entries neither overflow nor underflow. Nullopt for zero or non-finite.
std::optional<Eigen::Vector4d> NormalizedQuaternion(const Eigen::Vector4d& wxyz);

// Rotation vector (axis * angle, rad) taking `from` to `to`, expressed in the world frame.
Eigen::Vector3d OrientationError(const Eigen::Matrix3d& from, const Eigen::Matrix3d& to);

// Rotation matrix from an axis-angle vector (rad).
Eigen::Matrix3d RotationFromAxisAngle(const Eigen::Vector3d& axis_angle);

// Rotation from intrinsic X-Y-Z Euler angles [a, b, c] (rad): Rx(a) Ry(b) Rz(c), the "XYZ"
// convention of ManiSkill's end-effector controllers (pytorch3d's euler_angles_to_matrix).
Eigen::Matrix3d RotationFromEulerXyz(const Eigen::Vector3d& angles_rad);
// Its inverse: b in [-pi/2, pi/2], a and c in (-pi, pi].
Eigen::Vector3d EulerXyzFromRotation(const Eigen::Matrix3d& rotation);

// Angle (rad) between two orientations, in [0, pi].
double AngleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

}  // namespace culinarycut
