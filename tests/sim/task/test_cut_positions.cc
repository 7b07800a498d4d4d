// Tables of expected cut positions in the world for known boxes: the spec's fractions placed on
// the object's long axis (left = the robot's left, +y).
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "sim/task/cut_spec.h"
#include "sim/task/object_box.h"

namespace culinarycut::task {
namespace {

struct Row {
  CutState state;
  double ratio;
  DirectionalReference reference;
  int pieces;
  std::vector<double> expected_y_m;  // world y of each cut on the axis, left to right
};

// A 0.20 m cucumber lying along y, centred at y = 0.02 m: left end y = 0.12, right end y = -0.08.
ObjectBox CucumberAlongY() {
  ObjectBox box;
  box.name = "cucumber_0";
  box.food = "cucumber";
  box.pose.translation() = Eigen::Vector3d(0.5, 0.02, 0.04);
  box.pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  box.extent_m = Eigen::Vector3d(0.20, 0.04, 0.04);
  return box;
}

TEST_CASE("cut positions on a known box: middle, ratio from both sides, splits", "[task][positions]") {
  const std::vector<Row> table = {
      {CutState::kMiddle, 0.0, DirectionalReference::kNone, 0, {0.02}},
      {CutState::kRatio, 0.3, DirectionalReference::kLeft, 0, {0.06}},
      {CutState::kRatio, 0.3, DirectionalReference::kRight, 0, {-0.02}},
      {CutState::kRatio, 0.1, DirectionalReference::kLeft, 0, {0.10}},
      {CutState::kRatio, 0.9, DirectionalReference::kRight, 0, {0.10}},
      {CutState::kRatio, 0.25, DirectionalReference::kAlongLength, 0, {0.07}},
      {CutState::kSplit, 0.0, DirectionalReference::kNone, 3, {0.12 - 0.2 / 3, 0.12 - 0.4 / 3}},
      {CutState::kSplit, 0.0, DirectionalReference::kNone, 4, {0.07, 0.02, -0.03}},
      {CutState::kSplit, 0.0, DirectionalReference::kNone, 5, {0.08, 0.04, 0.0, -0.04}},
  };
  const ObjectBox box = CucumberAlongY();
  const LongAxis axis = LongAxisOf(box);
  for (const Row& row : table) {
    CutSpec spec;
    spec.state = row.state;
    spec.ratio = row.ratio;
    spec.reference = row.reference;
    spec.split_pieces = row.pieces;
    spec.target_object = "cucumber";
    INFO(Describe(spec));
    const std::vector<double> fractions = TargetFractionsFromLeft(spec);
    REQUIRE(fractions.size() == row.expected_y_m.size());
    for (size_t i = 0; i < fractions.size(); ++i) {
      const Eigen::Vector3d point = PointAtFraction(axis, fractions[i]);
      CHECK(point.x() == Approx(0.5));
      CHECK(point.y() == Approx(row.expected_y_m[i]).margin(1e-12));
      CHECK(point.z() == Approx(0.04));
    }
  }
}

TEST_CASE("cut positions on a box turned 60 deg follow its axis", "[task][positions]") {
  // A 0.30 m banana-sized box at (0.45, -0.1, 0.03), its long axis turned 60 deg from x: it
  // points (cos 60, sin 60) = towards +y, so its left end is the +y end.
  ObjectBox box = CucumberAlongY();
  box.food = "banana";
  box.pose.translation() = Eigen::Vector3d(0.45, -0.1, 0.03);
  box.pose.linear() = Eigen::AngleAxisd(M_PI / 3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  box.extent_m = Eigen::Vector3d(0.30, 0.04, 0.04);
  const LongAxis axis = LongAxisOf(box);
  const Eigen::Vector3d left_end(0.45 + 0.15 * 0.5, -0.1 + 0.15 * std::sqrt(3.0) / 2, 0.03);
  CHECK((axis.left_end_m - left_end).norm() < 1e-12);
  CutSpec spec;
  spec.state = CutState::kRatio;
  spec.ratio = 0.2;
  spec.reference = DirectionalReference::kRight;
  spec.target_object = "banana";
  // 0.2 from the right end = 0.8 from the left: 0.24 m along the axis from the left end.
  const Eigen::Vector3d expected = left_end - 0.24 * Eigen::Vector3d(0.5, std::sqrt(3.0) / 2, 0.0);
  CHECK((PointAtFraction(axis, TargetFractionsFromLeft(spec)[0]) - expected).norm() < 1e-12);
}

}  // namespace
}  // namespace culinarycut::task
