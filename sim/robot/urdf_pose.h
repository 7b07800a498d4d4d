// A URDF origin (xyz, rpy read as a quaternion by urdfdom) as an Eigen isometry.
#pragma once

#include <Eigen/Geometry>
#include <urdf_model/pose.h>

namespace culinarycut {

inline Eigen::Isometry3d IsometryFromUrdf(const urdf::Pose& pose) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.translation() << pose.position.x, pose.position.y, pose.position.z;
  out.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
                     .normalized()
                     .toRotationMatrix();
  return out;
}

}  // namespace culinarycut
