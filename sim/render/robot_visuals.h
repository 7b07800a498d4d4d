// The robot as the cameras see it: the meshes and materials of a RobotVisualDescription (read from
// the URDF by the robot description, never parsed here), each attached to the movable link that
// carries it, so the caller only supplies the poses of the base and of the movable links. Visuals
// of links whose name starts with "knife" are the knife.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sim/core/robot_visual_description.h"
#include "sim/render/material.h"
#include "sim/render/triangle_mesh.h"

namespace culinarycut::render {

struct RobotVisualPart {
  std::string link_name;  // the URDF link the visual belongs to
  int owner = 0;          // 0 = base (root link), i + 1 = i-th movable link
  Eigen::Isometry3d in_owner = Eigen::Isometry3d::Identity();  // mesh frame in the owner's frame
  TriangleMesh mesh;      // in the mesh frame, scale applied
  Material material;
  int segment = kRobotSegment;  // kRobotSegment or kKnifeSegment
};

struct RobotVisuals {
  std::string urdf_path;
  std::vector<std::string> owner_names;  // [0] = root link, [i + 1] = link moved by movable joint i
  std::vector<RobotVisualPart> parts;
  // Every URDF link: the owner it is merged into and its frame in the owner's frame.
  std::map<std::string, std::pair<int, Eigen::Isometry3d>> link_frames;

  int pose_count() const { return static_cast<int>(owner_names.size()); }
};

// Builds the meshes (boxes, cylinders, spheres; mesh files through assimp) and materials. Throws
// RenderError with the file and the reason when a mesh file cannot be read.
RobotVisuals BuildRobotVisuals(const RobotVisualDescription& description);

}  // namespace culinarycut::render
