// The robot as the cameras see it: every <visual> of the URDF, attached to the movable link that
// carries it. Fixed links are merged into their parent's movable link, with their fixed offset
// (the rule of sim/robot/robot_description.cc), so the caller only supplies the poses of the base
// and of the movable links. Visuals of links whose name starts with "knife" are the knife.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

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

// Reads the URDF's visuals (box, cylinder, sphere; meshes through assimp, path relative to the
// URDF, "file://" accepted). Movable joints (revolute, continuous, prismatic) are numbered in
// depth-first order from the root, which for a serial arm is the order of
// RobotDescription::links. Throws RenderError with the file and the reason.
RobotVisuals LoadRobotVisuals(const std::string& urdf_path);

}  // namespace culinarycut::render
