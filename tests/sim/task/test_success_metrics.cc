#include "sim/task/success_metrics.h"

#include <cmath>

#include <catch2/catch.hpp>

namespace culinarycut::task {
namespace {

// A 0.20 m cucumber lying along y at (0.5, 0, 0.04): left end at y = +0.1, right end at y = -0.1.
ObjectBox Cucumber(const std::string& name = "cucumber_0") {
  ObjectBox box;
  box.name = name;
  box.food = "cucumber";
  box.pose.translation() = Eigen::Vector3d(0.5, 0.0, 0.04);
  box.pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  box.extent_m = Eigen::Vector3d(0.20, 0.04, 0.04);
  return box;
}

CutSpec Ratio(double ratio, DirectionalReference side) {
  CutSpec spec;
  spec.state = CutState::kRatio;
  spec.ratio = ratio;
  spec.reference = side;
  spec.target_object = "cucumber";
  return spec;
}

CutSpec Split(int pieces) {
  CutSpec spec;
  spec.state = CutState::kSplit;
  spec.split_pieces = pieces;
  spec.target_object = "cucumber";
  return spec;
}

// A vertical cut perpendicular to the cucumber at `fraction` from its left end.
MeasuredCut CutAt(const ObjectBox& box, double fraction,
                  const Eigen::Vector3d& normal = Eigen::Vector3d(0, -1, 0)) {
  const LongAxis axis = LongAxisOf(box);
  MeasuredCut cut;
  cut.object_name = box.name;
  cut.plane_point_m = PointAtFraction(axis, fraction) + Eigen::Vector3d(0.003, 0.0, 0.01);
  cut.plane_normal = normal;
  return cut;
}

TEST_CASE("long axis runs from the robot's left (+y) to its right", "[task][metrics]") {
  const LongAxis axis = LongAxisOf(Cucumber());
  CHECK(axis.length_m == Approx(0.20));
  CHECK(axis.left_end_m.y() == Approx(0.1));
  CHECK(axis.direction.y() == Approx(-1.0));
}

TEST_CASE("a cut exactly at the tolerance succeeds, just beyond fails", "[task][metrics]") {
  const ObjectBox box = Cucumber();
  const CutSpec spec = Ratio(0.3, DirectionalReference::kLeft);
  TaskScore at_edge = ScoreCuts(box, spec, {CutAt(box, 0.4)});
  CHECK(at_edge.success);
  CHECK(at_edge.required[0].position_error_fraction == Approx(0.1));
  TaskScore beyond = ScoreCuts(box, spec, {CutAt(box, 0.4 + 1e-6)});
  CHECK_FALSE(beyond.success);
  CHECK_THAT(beyond.summary, Catch::Contains("off by 10.0% of the length"));
  CHECK(ScoreCuts(box, spec, {CutAt(box, 0.2)}).success);
}

TEST_CASE("a ratio cut measured from the wrong side fails", "[task][metrics]") {
  const ObjectBox box = Cucumber();
  const TaskScore score = ScoreCuts(box, Ratio(0.3, DirectionalReference::kRight), {CutAt(box, 0.3)});
  CHECK_FALSE(score.success);
  CHECK(score.required[0].target_fraction == Approx(0.7));
  CHECK(score.required[0].position_error_fraction == Approx(0.4));
  CHECK(ScoreCuts(box, Ratio(0.3, DirectionalReference::kRight), {CutAt(box, 0.7)}).success);
}

TEST_CASE("a split with one cut missing reports partial success", "[task][metrics]") {
  const ObjectBox box = Cucumber();
  const TaskScore all = ScoreCuts(box, Split(4), {CutAt(box, 0.76), CutAt(box, 0.27), CutAt(box, 0.5)});
  CHECK(all.success);
  CHECK(all.cuts_correct == 3);

  const TaskScore missing = ScoreCuts(box, Split(4), {CutAt(box, 0.25), CutAt(box, 0.75)});
  CHECK_FALSE(missing.success);
  CHECK(missing.cuts_required == 3);
  CHECK(missing.cuts_correct == 2);
  CHECK_FALSE(missing.required[1].placed);
  CHECK_THAT(missing.summary, Catch::Contains("2 of 3") && Catch::Contains("target 50.0%: no cut"));
}

TEST_CASE("matching places as many cuts within tolerance as possible", "[task][metrics]") {
  const ObjectBox box = Cucumber();
  SuccessTolerances wide;
  wide.position_fraction = 0.15;
  // Targets 0.2, 0.4, 0.6, 0.8. The cut at 0.33 is closest to 0.4, but taking it there would leave
  // 0.52 with no target in reach; placed at 0.2 and 0.4 both count.
  const TaskScore score = ScoreCuts(box, Split(5), {CutAt(box, 0.33), CutAt(box, 0.52)}, wide);
  CHECK(score.cuts_within_position_tolerance == 2);
  CHECK(score.required[0].measured_fraction == Approx(0.33));
  CHECK(score.required[1].measured_fraction == Approx(0.52));
  CHECK_FALSE(score.required[2].placed);
}

TEST_CASE("a cut through another object fails the task", "[task][metrics]") {
  const ObjectBox target = Cucumber("cucumber_0");
  MeasuredCut elsewhere = CutAt(target, 0.5);
  elsewhere.object_name = "apple_1";
  const TaskScore score = ScoreCuts(target, Split(3), {CutAt(target, 1.0 / 3), CutAt(target, 2.0 / 3), elsewhere});
  CHECK(score.cuts_correct == 2);
  CHECK(score.wrong_object_cuts == 1);
  CHECK_FALSE(score.success);
  CHECK_THAT(score.summary, Catch::Contains("other than cucumber_0"));

  ObjectBox apple = target;
  apple.food = "apple";
  CHECK_THROWS_WITH(ScoreCuts(apple, Split(3), {}), Catch::Contains("is a apple but the task asks"));
}

TEST_CASE("an extra slice fails unless allowed", "[task][metrics]") {
  const ObjectBox box = Cucumber();
  const CutSpec middle = Ratio(0.5, DirectionalReference::kLeft);
  const TaskScore score = ScoreCuts(box, middle, {CutAt(box, 0.5), CutAt(box, 0.2)});
  CHECK(score.extra_cuts == 1);
  CHECK_FALSE(score.success);
  SuccessTolerances lenient;
  lenient.allow_extra_cuts = true;
  CHECK(ScoreCuts(box, middle, {CutAt(box, 0.5), CutAt(box, 0.2)}, lenient).success);
}

TEST_CASE("the blade plane angle is checked against the target plane", "[task][metrics]") {
  const ObjectBox box = Cucumber();
  const CutSpec spec = Ratio(0.5, DirectionalReference::kLeft);
  auto tilted = [](double angle_rad) {  // normal rotated about the vertical by angle_rad
    return Eigen::Vector3d(std::sin(angle_rad), -std::cos(angle_rad), 0.0);
  };
  const TaskScore within = ScoreCuts(box, spec, {CutAt(box, 0.5, tilted(8.9 * M_PI / 180))});
  CHECK(within.success);
  CHECK(within.required[0].angle_error_rad == Approx(8.9 * M_PI / 180));
  const TaskScore beyond = ScoreCuts(box, spec, {CutAt(box, 0.5, tilted(9.1 * M_PI / 180))});
  CHECK_FALSE(beyond.success);
  CHECK_THAT(beyond.summary, Catch::Contains("cut surface off by 9.1 deg"));
}

TEST_CASE("the blade's orientation in the food is scored beside the cut surface's", "[task][metrics]") {
  const ObjectBox box = Cucumber();
  const CutSpec spec = Ratio(0.5, DirectionalReference::kLeft);
  MeasuredCut cut = CutAt(box, 0.5);  // a square cut surface
  cut.blade_normal = Eigen::Vector3d(0.0, 1.0, 0.0);  // sign-free: the blade's face normal either way
  const TaskScore square = ScoreCuts(box, spec, {cut});
  CHECK(square.success);
  CHECK(square.required[0].blade_angle_measured);
  CHECK(square.required[0].blade_angle_error_rad == Approx(0.0).margin(1e-12));
  // The blade twisted 15 deg about the vertical while the surface came out square: the cut fails.
  cut.blade_normal = Eigen::Vector3d(std::sin(15 * M_PI / 180), -std::cos(15 * M_PI / 180), 0.0);
  const TaskScore twisted = ScoreCuts(box, spec, {cut});
  CHECK_FALSE(twisted.success);
  CHECK(twisted.required[0].position_ok);
  CHECK(twisted.required[0].blade_angle_error_rad == Approx(15 * M_PI / 180));
  CHECK_THAT(twisted.summary, Catch::Contains("cut surface off by 0.0 deg, blade off by 15.0 deg"));
  // A vertical blade on a bias task fails however the surface came out.
  CutSpec bias = spec;
  bias.style = CutStyle::kBias;
  MeasuredCut vertical_blade = CutAt(box, 0.5, Eigen::Vector3d(0.0, -std::cos(0.44), std::sin(0.44)));
  vertical_blade.blade_normal = Eigen::Vector3d(0.0, -1.0, 0.0);
  const TaskScore vertical = ScoreCuts(box, bias, {vertical_blade});
  CHECK(vertical.required[0].angle_error_rad == Approx(0.0).margin(1e-12));
  CHECK(vertical.required[0].blade_angle_error_rad == Approx(0.35));
  CHECK_FALSE(vertical.success);
}

TEST_CASE("a bias cut must be tilted about the blade edge", "[task][metrics]") {
  const ObjectBox box = Cucumber();
  CutSpec spec = Ratio(0.5, DirectionalReference::kLeft);
  spec.style = CutStyle::kBias;
  auto tilted_about_edge = [](double tilt_rad) {
    return Eigen::Vector3d(0.0, -std::cos(tilt_rad), std::sin(tilt_rad));
  };
  // A plane tilted by 25 deg crossing the axis at the middle.
  CHECK(ScoreCuts(box, spec, {CutAt(box, 0.5, tilted_about_edge(25 * M_PI / 180))}).success);
  // A vertical plane is not a bias cut: 20 deg short of the range, beyond 9 deg.
  const TaskScore vertical = ScoreCuts(box, spec, {CutAt(box, 0.5)});
  CHECK_FALSE(vertical.success);
  CHECK(vertical.required[0].angle_error_rad == Approx(0.35));
}

TEST_CASE("a tilted plane is placed where it meets the long axis", "[task][metrics]") {
  const ObjectBox box = Cucumber();
  const LongAxis axis = LongAxisOf(box);
  MeasuredCut cut;
  cut.object_name = box.name;
  const Eigen::Vector3d normal(0.0, -std::cos(0.5), std::sin(0.5));
  // A point 0.02 m above the axis on a plane crossing the axis at fraction 0.3.
  const Eigen::Vector3d on_axis = PointAtFraction(axis, 0.3);
  const Eigen::Vector3d in_plane = normal.cross(Eigen::Vector3d::UnitX()).normalized();
  cut.plane_point_m = on_axis + 0.02 * in_plane;
  cut.plane_normal = normal;
  CHECK(*CutFractionAlongAxis(axis, cut) == Approx(0.3));
  cut.plane_normal = Eigen::Vector3d::UnitX();  // parallel to the axis: never crosses it
  CHECK_FALSE(CutFractionAlongAxis(axis, cut).has_value());
}

TEST_CASE("cuts from piece bounds sit between neighbouring pieces", "[task][metrics]") {
  const ObjectBox box = Cucumber();
  // Three pieces along y: [0.1, 0.035], [0.03, -0.035], [-0.04, -0.1] (left to right).
  const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pieces = {
      {{0.48, -0.1, 0.02}, {0.52, -0.04, 0.06}},
      {{0.48, 0.035, 0.02}, {0.52, 0.1, 0.06}},
      {{0.48, -0.035, 0.02}, {0.52, 0.03, 0.06}}};
  const auto cuts = CutsFromPieceBounds(box, pieces);
  REQUIRE(cuts.size() == 2);
  const TaskScore score = ScoreCuts(box, Split(3), cuts);
  CHECK(score.success);
  CHECK_FALSE(score.required[0].angle_measured);
  CHECK(score.required[0].measured_fraction == Approx((0.1 - 0.0325) / 0.2));
}

TEST_CASE("the partial-success table counts exactly-k correct cuts", "[task][metrics]") {
  const ObjectBox box = Cucumber();
  PartialSuccessTable table;
  table.Add(Split(3), ScoreCuts(box, Split(3), {CutAt(box, 1.0 / 3)}));
  table.Add(Split(3), ScoreCuts(box, Split(3), {CutAt(box, 0.9)}));
  table.Add(Split(3), ScoreCuts(box, Split(3), {CutAt(box, 1.0 / 3), CutAt(box, 2.0 / 3)}));
  table.Add(Ratio(0.3, DirectionalReference::kLeft), TaskScore{});  // not a split: ignored
  CHECK(table.Counts("cucumber", 3) == std::vector<int>{1, 1, 1});
  // The paper's table counts position only: a cut in place at a wrong angle still counts.
  table.Add(Split(3), ScoreCuts(box, Split(3), {CutAt(box, 1.0 / 3, Eigen::Vector3d(0.5, -0.8660254, 0))}));
  CHECK(table.Counts("cucumber", 3) == std::vector<int>{1, 2, 1});
  CHECK_THAT(table.ToMarkdown(), Catch::Contains("| cucumber | 1/3 | 4 | 50.0% | 25.0% | -- | -- |"));
}

}  // namespace
}  // namespace culinarycut::task
