#include "sim/task/object_box.h"

#include <algorithm>
#include <cmath>

#include "sim/task/cut_spec.h"

namespace culinarycut::task {
namespace {

constexpr double kOrthonormalTolerance = 1e-6;
// An axis closer than 45 deg to vertical cannot be the long axis of a food lying down.
const double kMaxVerticalComponent = std::sqrt(0.5) + 1e-12;
// Lying axes within this fraction of the longest count as equally long (round foods: apple, orange):
// the long axis is then the one nearest the robot's left-right, so a tiny change of size cannot
// turn the cut by 90 deg and "left" keeps meaning the robot's left.
constexpr double kRoundShapeTolerance = 0.15;
// An axis with less sideways (y) component than this counts as pointing straight along x.
constexpr double kSidewaysTieTolerance = 1e-9;

// Half extent of the box projected on world z.
double HalfHeight(const ObjectBox& box) {
  const Eigen::Matrix3d& axes = box.pose.linear();
  double half = 0.0;
  for (int i = 0; i < 3; ++i) half += 0.5 * box.extent_m[i] * std::abs(axes(2, i));
  return half;
}

}  // namespace

void ValidateObjectBox(const ObjectBox& box) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(box.extent_m[i]) || box.extent_m[i] <= 0.0) {
      throw TaskError("object '" + box.name + "' has a non-positive or non-finite extent; every "
                      "side length must be > 0 m");
    }
  }
  if (!box.pose.matrix().allFinite()) {
    throw TaskError("object '" + box.name + "' has a non-finite pose");
  }
  const Eigen::Matrix3d& rotation = box.pose.linear();
  if (!(rotation.transpose() * rotation).isIdentity(kOrthonormalTolerance) ||
      rotation.determinant() < 0.0) {
    throw TaskError("object '" + box.name + "' pose is not a rotation (use a unit quaternion)");
  }
}

LongAxis LongAxisOf(const ObjectBox& box) {
  const Eigen::Matrix3d& axes = box.pose.linear();
  double longest_m = 0.0;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(axes(2, i)) <= kMaxVerticalComponent) longest_m = std::max(longest_m, box.extent_m[i]);
  }
  // Of the lying axes about as long as the longest, the one closest to the robot's left-right.
  int best = -1;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(axes(2, i)) > kMaxVerticalComponent) continue;
    if (box.extent_m[i] < (1.0 - kRoundShapeTolerance) * longest_m) continue;
    if (best < 0 || std::abs(axes(1, i)) > std::abs(axes(1, best))) best = i;
  }
  if (best < 0) best = 0;  // unreachable for a rotation: at most one axis is near vertical
  Eigen::Vector3d direction = axes.col(best);
  const bool points_left = direction.y() > kSidewaysTieTolerance;
  const bool points_toward_robot =
      std::abs(direction.y()) <= kSidewaysTieTolerance && direction.x() < 0.0;
  if (points_left || points_toward_robot) direction = -direction;

  LongAxis axis;
  axis.direction = direction;
  axis.length_m = box.extent_m[best];
  axis.left_end_m = box.pose.translation() - 0.5 * axis.length_m * direction;
  axis.right_end_m = box.pose.translation() + 0.5 * axis.length_m * direction;
  return axis;
}

Eigen::Vector3d PointAtFraction(const LongAxis& axis, double fraction) {
  return axis.left_end_m + fraction * axis.length_m * axis.direction;
}

double BottomZ(const ObjectBox& box) { return box.pose.translation().z() - HalfHeight(box); }
double TopZ(const ObjectBox& box) { return box.pose.translation().z() + HalfHeight(box); }

}  // namespace culinarycut::task
