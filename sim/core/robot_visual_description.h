// How the robot looks, as plain data: every <visual> of its URDF attached to the movable link that
// carries it (fixed links merged into their movable parent with their fixed offset). The robot
// description (sim/robot) reads it from the URDF it parses anyway; the renderer (sim/render) turns
// it into meshes. Neither depends on the other: this type is the contract between them.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

namespace culinarycut {

struct VisualShape {
  enum class Kind { kBox, kCylinder, kSphere, kMesh };
  Kind kind = Kind::kBox;
  Eigen::Vector3d box_size_m = Eigen::Vector3d::Zero();  // full extents, kBox
  double radius_m = 0.0;                                  // kCylinder, kSphere
  double length_m = 0.0;                                  // kCylinder, along local z
  std::string mesh_path;                                  // kMesh: absolute path of the mesh file
  Eigen::Vector3d mesh_scale = Eigen::Vector3d::Ones();   // kMesh
};

struct RobotVisual {
  std::string link_name;  // the URDF link the visual belongs to
  int owner = 0;          // 0 = base (root link), i + 1 = i-th movable link in depth-first order
  Eigen::Isometry3d in_owner = Eigen::Isometry3d::Identity();  // shape frame in the owner's frame
  VisualShape shape;
  std::optional<Eigen::Vector3f> srgb_color;  // the URDF material's colour, when it gives one
};

struct RobotVisualDescription {
  std::string urdf_path;                 // where it was read from (for messages)
  std::vector<std::string> owner_names;  // [0] = root link, [i + 1] = link moved by movable joint i
  std::vector<RobotVisual> visuals;
  // Every URDF link: the owner it is merged into and its frame in the owner's frame.
  std::map<std::string, std::pair<int, Eigen::Isometry3d>> link_frames;
};

}  // namespace culinarycut
