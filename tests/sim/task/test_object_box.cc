#include "sim/task/object_box.h"

#include <cmath>

#include <catch2/catch.hpp>

#include "sim/task/cut_spec.h"

namespace culinarycut::task {
namespace {

ObjectBox Box(const Eigen::Vector3d& extent_m, const Eigen::Matrix3d& rotation) {
  ObjectBox box;
  box.name = "box";
  box.food = "banana";
  box.pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.05);
  box.pose.linear() = rotation;
  box.extent_m = extent_m;
  return box;
}

Eigen::Matrix3d Yaw(double angle_rad) {
  return Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

TEST_CASE("the long axis points to the robot's right whatever way the box is turned",
          "[task][object_box]") {
  for (double yaw_deg : {-80.0, -30.0, 10.0, 60.0, 100.0, 150.0, 200.0}) {
    const LongAxis axis = LongAxisOf(Box({0.2, 0.05, 0.04}, Yaw(yaw_deg * M_PI / 180)));
    INFO("yaw " << yaw_deg << " deg");
    CHECK(axis.length_m == Approx(0.2));
    CHECK(axis.direction.y() < 0.0);
    CHECK(axis.left_end_m.y() > axis.right_end_m.y());
    CHECK((PointAtFraction(axis, 0.5) - Eigen::Vector3d(0.5, 0.0, 0.05)).norm() < 1e-12);
  }
}

TEST_CASE("an axis straight along x has its left end nearer the robot", "[task][object_box]") {
  const LongAxis axis = LongAxisOf(Box({0.2, 0.05, 0.04}, Yaw(M_PI)));
  CHECK(axis.direction.x() == Approx(1.0));
  CHECK(axis.left_end_m.x() == Approx(0.4));
}

TEST_CASE("a box standing on its long side uses its longest lying axis", "[task][object_box]") {
  // Longest extent (0.3 m) along the box z, which is vertical: the long axis is the box x (0.1 m).
  const ObjectBox standing = Box({0.1, 0.06, 0.3}, Eigen::Matrix3d::Identity());
  const LongAxis axis = LongAxisOf(standing);
  CHECK(axis.length_m == Approx(0.1));
  CHECK(BottomZ(standing) == Approx(0.05 - 0.15));
  CHECK(TopZ(standing) == Approx(0.05 + 0.15));
}

TEST_CASE("a round food's long axis is the robot's left-right, whatever tiny size change",
          "[task][object_box]") {
  for (const Eigen::Vector3d& extent : {Eigen::Vector3d(0.08, 0.08, 0.08),
                                        Eigen::Vector3d(0.0801, 0.08, 0.08),
                                        Eigen::Vector3d(0.08, 0.0801, 0.079),
                                        Eigen::Vector3d(0.09, 0.08, 0.07)}) {
    INFO("extent " << extent.transpose());
    const LongAxis axis = LongAxisOf(Box(extent, Eigen::Matrix3d::Identity()));
    CHECK(axis.direction.y() == Approx(-1.0));
  }
  // Turned 30 deg: the box axis nearer y (the box y, at 30 deg from world y) wins.
  const LongAxis turned = LongAxisOf(Box({0.08, 0.08, 0.08}, Yaw(M_PI / 6)));
  CHECK(std::abs(turned.direction.y()) == Approx(std::cos(M_PI / 6)));
  // A clearly elongated box keeps its own long axis even when it lies along x.
  CHECK(LongAxisOf(Box({0.10, 0.08, 0.08}, Eigen::Matrix3d::Identity())).direction.x() ==
        Approx(1.0));
}

TEST_CASE("bad boxes are refused", "[task][object_box]") {
  CHECK_THROWS_WITH(ValidateObjectBox(Box({0.1, 0.0, 0.1}, Eigen::Matrix3d::Identity())),
                    Catch::Contains("non-positive or non-finite extent"));
  Eigen::Matrix3d sheared = Eigen::Matrix3d::Identity();
  sheared(0, 1) = 0.5;
  CHECK_THROWS_WITH(ValidateObjectBox(Box({0.1, 0.1, 0.1}, sheared)),
                    Catch::Contains("not a rotation"));
}

}  // namespace
}  // namespace culinarycut::task
