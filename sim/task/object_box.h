// A food object as the task logic sees it: an oriented bounding box in the world frame, and the
// long axis that cut positions are measured along.
#pragma once

#include <string>

#include <Eigen/Geometry>

namespace culinarycut::task {

// World frame as in sim/core/scene_layout.h: z up, the robot base at the origin looking along +x.
// "Left" and "right" are the robot's: left is +y, right is -y.
struct ObjectBox {
  std::string name;               // instance name in the scene, e.g. "cucumber_0"
  std::string food;               // food type, e.g. "cucumber"
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // box centre and axes in the world
  Eigen::Vector3d extent_m = Eigen::Vector3d::Zero();      // full side lengths along the box axes
};

// The object's long axis, oriented from its left end to its right end.
struct LongAxis {
  Eigen::Vector3d left_end_m;   // world point where fraction 0 lies (on the axis through the centre)
  Eigen::Vector3d right_end_m;  // world point where fraction 1 lies
  Eigen::Vector3d direction;    // unit vector, left end -> right end
  double length_m = 0.0;
};

// Throws TaskError for a non-positive or non-finite extent or a non-orthonormal pose.
void ValidateObjectBox(const ObjectBox& box);

// The long axis: the longest box axis that is at least 45 deg from vertical (foods lie on the
// board); among lying axes within 15 % of the longest (round foods), the one nearest world y.
// Oriented so it points to the robot's right (-y); an axis exactly along x points away from the
// robot (+x), so "left" is then the end nearer the robot.
LongAxis LongAxisOf(const ObjectBox& box);

// World point at `fraction` (0 = left end, 1 = right end) of the long axis.
Eigen::Vector3d PointAtFraction(const LongAxis& axis, double fraction);

// Lowest and highest world z of the box's corners (m).
double BottomZ(const ObjectBox& box);
double TopZ(const ObjectBox& box);

}  // namespace culinarycut::task
