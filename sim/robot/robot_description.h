// A serial robot arm read from URDF: the movable joints from the root to a tip link, with every
// fixed link on the way merged into the movable link that carries it (sim/robot/rigid_bodies.h).
// Frames and units follow URDF (metres, radians, kilograms); "link frame i" is the frame of the link
// moved by joint i.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sim/core/robot_visual_description.h"

namespace culinarycut {

struct CollisionShape {
  enum class Kind { kBox, kCylinder, kSphere };
  Kind kind = Kind::kSphere;
  Eigen::Vector3d box_size_m = Eigen::Vector3d::Zero();  // full extents, kBox only
  double radius_m = 0.0;                                  // kCylinder and kSphere
  double length_m = 0.0;                                  // kCylinder, along the shape's local z
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // in the owning link frame
};

struct RigidLink {
  std::string name;
  double mass_kg = 0.0;
  Eigen::Vector3d center_of_mass_m = Eigen::Vector3d::Zero();        // in the link frame
  Eigen::Vector3d inertia_diagonal_kgm2 = Eigen::Vector3d::Zero();   // about the COM, link axes
  std::vector<CollisionShape> shapes;
};

struct JointLimits {
  double lower_rad = 0.0;
  double upper_rad = 0.0;
  double max_velocity_rad_s = 0.0;
  double max_effort_nm = 0.0;
};

struct RobotDescription {
  std::string name;
  RigidLink base;                               // fixed to the world at the robot base pose
  std::vector<std::string> joint_names;         // movable (revolute) joints, root to tip
  std::vector<Eigen::Isometry3d> joint_origins; // parent link frame -> joint frame at q = 0
  std::vector<Eigen::Vector3d> joint_axes;      // in the joint (child link) frame, unit length
  std::vector<JointLimits> limits;
  std::vector<RigidLink> links;                 // links[i] is moved by joint i
  // Fixed frames past the last movable joint (flange, knife frames, ...), in the last link frame.
  std::map<std::string, Eigen::Isometry3d> tip_frames;
  // How it looks (every URDF <visual>), read from the same parse, for the renderer.
  RobotVisualDescription visuals;

  int dof() const { return static_cast<int>(joint_names.size()); }
  // A tip frame by name; throws std::out_of_range with the known names if missing.
  const Eigen::Isometry3d& TipFrame(const std::string& name) const;
};

// Loads the chain from the URDF root to `tip_link`. Throws std::runtime_error with the file name
// and the reason on a missing file, parse error, unsupported joint type or unknown tip link.
RobotDescription LoadRobotDescription(const std::string& urdf_path, const std::string& tip_link);

}  // namespace culinarycut
