#include "sim/task/cut_planner.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

namespace culinarycut::task {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRate_hz = 1000.0;
constexpr double kTcpToTip_m = 0.10;  // the TCP is the middle of the 0.20 m edge
constexpr double kPlaneTolerance_m = 1e-3;

ObjectBox Box(const std::string& food, const Eigen::Vector3d& centre_m,
              const Eigen::Vector3d& extent_m, double yaw_rad) {
  ObjectBox box;
  box.name = food + "_0";
  box.food = food;
  box.pose = Eigen::Isometry3d::Identity();
  box.pose.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  box.pose.translation() = centre_m;
  box.extent_m = extent_m;
  return box;
}

// Lying on the board (top z = 0.02) along y, as a cucumber does.
ObjectBox Cucumber() { return Box("cucumber", {0.5, 0.0, 0.04}, {0.04, 0.20, 0.04}, 0.0); }
ObjectBox RotatedCucumber() {
  return Box("cucumber", {0.45, 0.05, 0.04}, {0.04, 0.20, 0.04}, kPi / 6.0);
}
ObjectBox Apple() { return Box("apple", {0.55, -0.05, 0.06}, {0.08, 0.08, 0.08}, 0.0); }

// Knife pointing down, blade along +x: the flange-down pose above the board.
Eigen::Isometry3d StartPose() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = Eigen::Vector3d::UnitX();
  pose.linear().col(1) = -Eigen::Vector3d::UnitY();
  pose.linear().col(2) = -Eigen::Vector3d::UnitZ();
  pose.translation() = Eigen::Vector3d(0.4, 0.0, 0.3);
  return pose;
}

CutSpec Spec(CutStyle style, CutState state, const std::string& food) {
  CutSpec spec;
  spec.style = style;
  spec.state = state;
  spec.target_object = food;
  return spec;
}

// Middle, ratio 0.3 from the left and from the right, splits into 3, 4 and 5.
std::vector<CutSpec> AllStates(CutStyle style, const std::string& food) {
  std::vector<CutSpec> specs = {Spec(style, CutState::kMiddle, food)};
  for (const auto reference : {DirectionalReference::kLeft, DirectionalReference::kRight}) {
    CutSpec spec = Spec(style, CutState::kRatio, food);
    spec.ratio = 0.3;
    spec.reference = reference;
    specs.push_back(spec);
  }
  for (int pieces = 3; pieces <= 5; ++pieces) {
    CutSpec spec = Spec(style, CutState::kSplit, food);
    spec.split_pieces = pieces;
    specs.push_back(spec);
  }
  return specs;
}

double PlaneDistance(const TrajectorySample& sample, const Eigen::Vector3d& point_m) {
  const Eigen::Vector3d normal = sample.tcp_pose.linear().col(1);
  return std::abs(normal.dot(point_m - sample.tcp_pose.translation()));
}

double AngleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

Eigen::Vector3d Tip(const TrajectorySample& sample) {
  return sample.tcp_pose.translation() + kTcpToTip_m * sample.tcp_pose.linear().col(0);
}

// Worst numbers over the sweep, for the summary check at the end.
struct Worst {
  double plane_distance_m = 0.0;
  double speed_fraction = 0.0;
  double turn_fraction = 0.0;
  double velocity_mismatch_m_s = 0.0;
};

// Largest value seen and when.
struct Extreme {
  double value = -1e300;
  double time_s = 0.0;
  void Update(double candidate, double t_s) {
    if (candidate > value) {
      value = candidate;
      time_s = t_s;
    }
  }
  std::string Describe(const CutTrajectory& plan) const {
    return std::to_string(value) + " at t = " + std::to_string(time_s) + " s (" +
           Name(plan.PhaseAt(time_s)) + ")";
  }
};

// Every generic property of one plan: the blade plane through each target during its cut, the
// workspace, both speed limits, continuity, analytic velocities against finite differences, the
// edge below the bottom at each cut end, and the phase layout.
void CheckPlan(const CutTrajectory& plan, const ObjectBox& box, const PlannerOptions& options,
               Worst* worst) {
  const std::vector<TrajectorySample> samples = plan.SampleUniform(kRate_hz);
  CHECK(samples.size() >= 2);
  if (samples.size() < 2) return;
  CHECK(samples.front().time_s == 0.0);
  CHECK(samples.back().time_s == Approx(plan.duration_s()));

  // Per-sample properties as worst values (with where they happen) and one check each.
  Extreme outside_m, speed_fraction, turn_fraction, jump_excess, mismatch_m_s;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const TrajectorySample& sample = samples[k];
    const double t_s = sample.time_s;
    const Eigen::Vector3d& tcp_m = sample.tcp_pose.translation();
    outside_m.Update(std::max((options.workspace_min_m - tcp_m).maxCoeff(),
                              (tcp_m - options.workspace_max_m).maxCoeff()),
                     t_s);
    speed_fraction.Update(sample.linear_velocity_m_s.norm() / options.max_linear_speed_m_s, t_s);
    turn_fraction.Update(sample.angular_velocity_rad_s.norm() / options.max_angular_speed_rad_s,
                         t_s);
    if (k == 0) continue;
    const TrajectorySample& before = samples[k - 1];
    const double dt_s = t_s - before.time_s;
    // No jump beyond what the speed limits allow between consecutive samples.
    jump_excess.Update(
        std::max((tcp_m - before.tcp_pose.translation()).norm() -
                     options.max_linear_speed_m_s * dt_s,
                 AngleBetween(before.tcp_pose.linear(), sample.tcp_pose.linear()) -
                     options.max_angular_speed_rad_s * dt_s),
        t_s);
    if (k + 1 < samples.size() && std::abs(samples[k + 1].time_s - t_s - dt_s) < 1e-12) {
      // Central differences against the analytic velocities.
      const TrajectorySample& after = samples[k + 1];
      const Eigen::Vector3d linear =
          (after.tcp_pose.translation() - before.tcp_pose.translation()) / (2.0 * dt_s);
      const Eigen::AngleAxisd turn(after.tcp_pose.linear() * before.tcp_pose.linear().transpose());
      const Eigen::Vector3d angular = turn.axis() * turn.angle() / (2.0 * dt_s);
      mismatch_m_s.Update(std::max((linear - sample.linear_velocity_m_s).norm(),
                                   (angular - sample.angular_velocity_rad_s).norm()),
                          t_s);
    }
  }
  INFO("worst workspace excess " << outside_m.Describe(plan));
  CHECK(outside_m.value <= 0.0);
  INFO("worst speed / limit " << speed_fraction.Describe(plan));
  CHECK(speed_fraction.value <= 1.0);
  INFO("worst angular speed / limit " << turn_fraction.Describe(plan));
  CHECK(turn_fraction.value <= 1.0);
  INFO("worst jump beyond v_max dt " << jump_excess.Describe(plan));
  CHECK(jump_excess.value <= 1e-12);
  INFO("worst finite-difference velocity mismatch " << mismatch_m_s.Describe(plan));
  CHECK(mismatch_m_s.value < 1e-3);
  worst->speed_fraction = std::max(worst->speed_fraction, speed_fraction.value);
  worst->turn_fraction = std::max(worst->turn_fraction, turn_fraction.value);
  worst->velocity_mismatch_m_s = std::max(worst->velocity_mismatch_m_s, mismatch_m_s.value);
  // At rest at both ends.
  CHECK(samples.front().linear_velocity_m_s.norm() < 1e-12);
  CHECK(samples.back().linear_velocity_m_s.norm() < 1e-12);

  const LongAxis axis = LongAxisOf(box);
  const std::vector<double> fractions = TargetFractionsFromLeft(plan.spec());
  CHECK(plan.cuts().size() == fractions.size());
  if (plan.cuts().size() != fractions.size()) return;
  for (std::size_t i = 0; i < fractions.size(); ++i) {
    const PlannedCut& cut = plan.cuts()[i];
    INFO("cut " << i + 1 << " of " << fractions.size());
    CHECK(cut.fraction_from_left == Approx(fractions[i]));
    CHECK((cut.target_point_m - PointAtFraction(axis, fractions[i])).norm() < 1e-12);
    CHECK(cut.end_time_s > cut.start_time_s);
    CHECK(plan.PhaseAt(0.5 * (cut.start_time_s + cut.end_time_s)) == SegmentPhase::kCut);
    // The blade plane through the target at every 1 kHz sample of the cut, ends included.
    Extreme distance_m, normal_change;
    std::vector<TrajectorySample> in_cut = {plan.Sample(cut.start_time_s)};
    for (const TrajectorySample& sample : samples) {
      if (sample.time_s > cut.start_time_s && sample.time_s < cut.end_time_s) {
        in_cut.push_back(sample);
      }
    }
    in_cut.push_back(plan.Sample(cut.end_time_s));
    for (const TrajectorySample& sample : in_cut) {
      distance_m.Update(PlaneDistance(sample, cut.target_point_m), sample.time_s);
      normal_change.Update(
          1.0 - std::abs(sample.tcp_pose.linear().col(1).dot(cut.blade_plane_normal)),
          sample.time_s);
    }
    worst->plane_distance_m = std::max(worst->plane_distance_m, distance_m.value);
    INFO("worst distance from the target to the blade plane " << distance_m.Describe(plan));
    CHECK(distance_m.value <= kPlaneTolerance_m);
    CHECK(normal_change.value < 1e-9);
    CHECK(cut.target_plane_normal.dot(axis.direction) > 0.0);
    // The whole edge ends below the bottom, by cut_end_below_bottom_m.
    const TrajectorySample end = plan.Sample(cut.end_time_s);
    const Eigen::Vector3d edge_x = end.tcp_pose.linear().col(0);
    for (const double along_m : {-kTcpToTip_m, kTcpToTip_m}) {
      const double z_m = (end.tcp_pose.translation() + along_m * edge_x).z();
      CHECK(z_m <= BottomZ(box) - options.cut_end_below_bottom_m + 1e-9);
    }
  }

  // Spans are contiguous; each cut is [transfer,] descend, cut, retreat.
  const auto spans = plan.Phases();
  CHECK(!spans.empty());
  if (spans.empty()) return;
  CHECK(spans.front().start_time_s == 0.0);
  CHECK(spans.back().end_time_s == Approx(plan.duration_s()));
  std::vector<SegmentPhase> after_approach;
  for (std::size_t k = 0; k < spans.size(); ++k) {
    if (k > 0) CHECK(spans[k].start_time_s == spans[k - 1].end_time_s);
    if (spans[k].phase != SegmentPhase::kApproach) after_approach.push_back(spans[k].phase);
  }
  std::vector<SegmentPhase> expected;
  for (std::size_t i = 0; i < fractions.size(); ++i) {
    if (i > 0) expected.push_back(SegmentPhase::kTransfer);
    expected.insert(expected.end(),
                    {SegmentPhase::kDescend, SegmentPhase::kCut, SegmentPhase::kRetreat});
  }
  CHECK(after_approach == expected);
}

// Bias: the blade normal leaves the horizontal by the sampled angle and the TCP drifts along the
// tilted plane, right (along the long axis) while it descends.
void CheckBias(const CutTrajectory& plan, const ObjectBox& box, const PlannerOptions& options) {
  const double angle_rad = plan.parameters().bias_angle_rad;
  CHECK(angle_rad >= options.bias_angle_rad.min);
  CHECK(angle_rad <= options.bias_angle_rad.max);
  const Eigen::Vector3d along = LongAxisOf(box).direction;
  for (const PlannedCut& cut : plan.cuts()) {
    const TrajectorySample start = plan.Sample(cut.start_time_s);
    const TrajectorySample end = plan.Sample(cut.end_time_s);
    const Eigen::Vector3d normal = start.tcp_pose.linear().col(1);
    CHECK(std::asin(std::abs(normal.z())) == Approx(angle_rad).margin(1e-9));
    CHECK(std::abs(cut.target_plane_normal.dot(normal)) == Approx(1.0).margin(1e-12));
    const Eigen::Vector3d travel_m = end.tcp_pose.translation() - start.tcp_pose.translation();
    CHECK(travel_m.dot(along) == Approx(-travel_m.z() * std::tan(angle_rad)).margin(1e-9));
    CHECK(travel_m.dot(along) > 0.0);
  }
}

// Guillotine: the tip stays put (1 mm) while the blade turns from the sampled pitch to flat.
void CheckGuillotine(const CutTrajectory& plan, const PlannerOptions& options) {
  const double pitch_rad = plan.parameters().guillotine_start_pitch_rad;
  CHECK(pitch_rad >= options.guillotine_start_pitch_rad.min);
  for (const PlannedCut& cut : plan.cuts()) {
    const TrajectorySample start = plan.Sample(cut.start_time_s);
    const TrajectorySample end = plan.Sample(cut.end_time_s);
    CHECK(std::asin(-start.tcp_pose.linear()(2, 0)) == Approx(pitch_rad).margin(1e-9));
    CHECK(std::abs(end.tcp_pose.linear()(2, 0)) < 1e-9);  // edge flat at the end
    double worst_tip_m = 0.0;
    for (int k = 0; k <= 50; ++k) {
      const double t_s = cut.start_time_s + (cut.end_time_s - cut.start_time_s) * k / 50.0;
      worst_tip_m = std::max(worst_tip_m, (Tip(plan.Sample(t_s)) - Tip(start)).norm());
    }
    CHECK(worst_tip_m < 1e-3);
    // Blade vertical, across the long axis.
    CHECK(std::abs(cut.blade_plane_normal.z()) < 1e-9);
  }
}

// Saw: back and forth along the blade at the sampled frequency, within the sampled amplitude.
void CheckSaw(const CutTrajectory& plan) {
  const double frequency_hz = plan.parameters().saw_frequency_hz;
  const double amplitude_m = plan.parameters().saw_amplitude_m;
  CHECK(frequency_hz > 0.0);
  CHECK(amplitude_m > 0.0);
  for (const PlannedCut& cut : plan.cuts()) {
    const Eigen::Vector3d blade_x = plan.Sample(cut.start_time_s).tcp_pose.linear().col(0);
    const Eigen::Vector3d origin_m = plan.Sample(cut.start_time_s).tcp_pose.translation();
    std::vector<double> crossings_s;
    double previous = 0.0;
    double peak_m = 0.0;
    for (double t_s = cut.start_time_s; t_s <= cut.end_time_s; t_s += 1e-3) {
      const double offset_m = (plan.Sample(t_s).tcp_pose.translation() - origin_m).dot(blade_x);
      peak_m = std::max(peak_m, std::abs(offset_m));
      if (previous != 0.0 && offset_m != 0.0 && (previous < 0.0) != (offset_m < 0.0)) {
        crossings_s.push_back(t_s);
      }
      if (offset_m != 0.0) previous = offset_m;
    }
    CHECK(crossings_s.size() >= 6);  // at least three full strokes per cut
    if (crossings_s.size() < 3) continue;
    const double measured_hz = (crossings_s.size() - 1) /
                               (2.0 * (crossings_s.back() - crossings_s.front()));
    CHECK(measured_hz == Approx(frequency_hz).epsilon(0.02));
    CHECK(peak_m <= amplitude_m + 1e-9);
    CHECK(peak_m >= 0.5 * amplitude_m);
  }
}

TEST_CASE("every style and state: blade plane through the targets, within workspace and limits",
          "[task][planner]") {
  const PlannerOptions options;
  Worst worst;
  for (const ObjectBox& box : {Cucumber(), RotatedCucumber(), Apple()}) {
    for (const CutStyle style :
         {CutStyle::kNormal, CutStyle::kBias, CutStyle::kGuillotine, CutStyle::kSaw}) {
      for (const CutSpec& spec : AllStates(style, box.food)) {
        for (const std::uint64_t seed : {1u, 7u, 42u}) {
          INFO(Describe(spec) << ", box at " << box.pose.translation().transpose()
                              << ", seed " << seed);
          const CutTrajectory plan = PlanCutTrajectory(box, spec, StartPose(), options, seed);
          CheckPlan(plan, box, options, &worst);
          if (style == CutStyle::kBias) CheckBias(plan, box, options);
          if (style == CutStyle::kGuillotine) CheckGuillotine(plan, options);
          if (style == CutStyle::kSaw) CheckSaw(plan);
        }
      }
    }
  }
  CHECK(worst.plane_distance_m < kPlaneTolerance_m);
  CHECK(worst.speed_fraction <= 1.0);
  CHECK(worst.turn_fraction <= 1.0);
}

TEST_CASE("sampled parameters come from their ranges and are used", "[task][planner]") {
  const PlannerOptions options;
  const ObjectBox box = Cucumber();
  for (const std::uint64_t seed : {3u, 4u, 5u}) {
    const CutTrajectory plan =
        PlanCutTrajectory(box, Spec(CutStyle::kNormal, CutState::kMiddle, "cucumber"),
                          StartPose(), options, seed);
    const SampledCutParameters& drawn = plan.parameters();
    CHECK(drawn.cut_start_height_m >= options.cut_start_height_m.min);
    CHECK(drawn.cut_start_height_m <= options.cut_start_height_m.max);
    CHECK(drawn.cut_speed_m_s >= options.cut_speed_m_s.min);
    CHECK(drawn.cut_speed_m_s <= options.cut_speed_m_s.max);
    CHECK(drawn.bias_angle_rad == 0.0);  // other styles' parameters stay zero
    CHECK(drawn.saw_frequency_hz == 0.0);
    const PlannedCut& cut = plan.cuts().front();
    // The cut starts with the edge at the sampled height over the top and runs at the sampled
    // speed through the food.
    CHECK(plan.Sample(cut.start_time_s).tcp_pose.translation().z() ==
          Approx(TopZ(box) + drawn.cut_start_height_m).margin(1e-12));
    const double mid_s = 0.5 * (cut.start_time_s + cut.end_time_s);
    CHECK(plan.Sample(mid_s).linear_velocity_m_s.norm() == Approx(drawn.cut_speed_m_s));
    CHECK(plan.Sample(mid_s).linear_velocity_m_s.z() < 0.0);
  }
}

TEST_CASE("the blade tip points away from the robot", "[task][planner]") {
  const PlannerOptions options;
  for (const ObjectBox& box : {Cucumber(), RotatedCucumber()}) {
    const CutTrajectory plan =
        PlanCutTrajectory(box, Spec(CutStyle::kNormal, CutState::kMiddle, "cucumber"),
                          StartPose(), options, 1);
    const Eigen::Vector3d blade_x =
        plan.Sample(plan.cuts().front().start_time_s).tcp_pose.linear().col(0);
    Eigen::Vector3d outward = box.pose.translation();
    outward.z() = 0.0;
    CHECK(blade_x.dot(outward.normalized()) > 0.5);
    CHECK(std::abs(blade_x.z()) < 1e-12);
  }
}

TEST_CASE("same seed gives the same trajectory, another seed other parameters",
          "[task][planner]") {
  const PlannerOptions options;
  const ObjectBox box = RotatedCucumber();
  for (const CutStyle style :
       {CutStyle::kNormal, CutStyle::kBias, CutStyle::kGuillotine, CutStyle::kSaw}) {
    CutSpec spec = Spec(style, CutState::kSplit, "cucumber");
    spec.split_pieces = 4;
    const CutTrajectory a = PlanCutTrajectory(box, spec, StartPose(), options, 11);
    const CutTrajectory b = PlanCutTrajectory(box, spec, StartPose(), options, 11);
    const CutTrajectory c = PlanCutTrajectory(box, spec, StartPose(), options, 12);
    REQUIRE(a.duration_s() == b.duration_s());
    const auto samples_a = a.SampleUniform(100.0);
    const auto samples_b = b.SampleUniform(100.0);
    REQUIRE(samples_a.size() == samples_b.size());
    for (std::size_t k = 0; k < samples_a.size(); ++k) {
      CHECK(samples_a[k].tcp_pose.matrix() == samples_b[k].tcp_pose.matrix());
      CHECK(samples_a[k].linear_velocity_m_s == samples_b[k].linear_velocity_m_s);
    }
    CHECK(a.parameters().cut_speed_m_s != c.parameters().cut_speed_m_s);
    CHECK(a.parameters().cut_start_height_m != c.parameters().cut_start_height_m);
    if (style == CutStyle::kBias) {
      CHECK(a.parameters().bias_angle_rad != c.parameters().bias_angle_rad);
    }
    if (style == CutStyle::kSaw) {
      CHECK(a.parameters().saw_frequency_hz != c.parameters().saw_frequency_hz);
    }
  }
}

TEST_CASE("outside the plan the knife rests at the first or last pose", "[task][planner]") {
  const CutTrajectory plan =
      PlanCutTrajectory(Cucumber(), Spec(CutStyle::kSaw, CutState::kMiddle, "cucumber"),
                        StartPose(), PlannerOptions{}, 2);
  const TrajectorySample before = plan.Sample(-1.0);
  CHECK(before.time_s == -1.0);
  CHECK(before.tcp_pose.isApprox(StartPose(), 1e-12));
  CHECK(before.linear_velocity_m_s.norm() == 0.0);
  const TrajectorySample after = plan.Sample(plan.duration_s() + 1.0);
  CHECK(after.tcp_pose.isApprox(plan.Sample(plan.duration_s()).tcp_pose, 1e-12));
  CHECK(after.linear_velocity_m_s.norm() == 0.0);
  CHECK(after.angular_velocity_rad_s.norm() == 0.0);
  CHECK(plan.PhaseAt(plan.duration_s() + 1.0) == SegmentPhase::kRetreat);
  CHECK(plan.PhaseAt(0.0) == SegmentPhase::kApproach);
  CHECK(Name(SegmentPhase::kTransfer) == "transfer");
}

TEST_CASE("bad inputs are refused with a message", "[task][planner]") {
  const ObjectBox cucumber = Cucumber();
  const CutSpec middle = Spec(CutStyle::kNormal, CutState::kMiddle, "cucumber");

  PlannerOptions inverted;
  inverted.cut_speed_m_s = {0.05, 0.02};
  CHECK_THROWS_WITH(PlanCutTrajectory(cucumber, middle, StartPose(), inverted, 1),
                    Catch::Contains("cut_speed_m_s is an inverted range"));
  PlannerOptions too_fast;
  too_fast.cut_speed_m_s = {0.1, 0.5};
  CHECK_THROWS_WITH(ValidatePlannerOptions(too_fast), Catch::Contains("cut_speed_m_s"));
  PlannerOptions no_limit;
  no_limit.max_angular_speed_rad_s = 0.0;
  CHECK_THROWS_WITH(ValidatePlannerOptions(no_limit), Catch::Contains("max_angular_speed_rad_s"));

  // A cutting board's worth of food: wider along the blade than the blade covers.
  const ObjectBox slab = Box("melon", {0.5, 0.0, 0.04}, {0.22, 0.30, 0.04}, 0.0);
  CHECK_THROWS_WITH(
      PlanCutTrajectory(slab, Spec(CutStyle::kGuillotine, CutState::kMiddle, "melon"),
                        StartPose(), PlannerOptions{}, 1),
      Catch::Contains("wide along the blade"));
  CHECK_NOTHROW(PlanCutTrajectory(slab, Spec(CutStyle::kNormal, CutState::kMiddle, "melon"),
                                  StartPose(), PlannerOptions{}, 1));

  // The clearance height above the workspace's ceiling.
  PlannerOptions low_ceiling;
  low_ceiling.workspace_max_m.z() = 0.1;
  CHECK_THROWS_WITH(PlanCutTrajectory(cucumber, middle, StartPose(), low_ceiling, 1),
                    Catch::Contains("leaves the workspace") && Catch::Contains("approach"));
  // A ratio cut near the workspace's left edge.
  const ObjectBox far_left = Box("cucumber", {0.5, 0.55, 0.04}, {0.04, 0.20, 0.04}, 0.0);
  CutSpec left_ratio = Spec(CutStyle::kNormal, CutState::kRatio, "cucumber");
  left_ratio.ratio = 0.1;
  left_ratio.reference = DirectionalReference::kLeft;
  CHECK_THROWS_WITH(PlanCutTrajectory(far_left, left_ratio, StartPose(), PlannerOptions{}, 1),
                    Catch::Contains("leaves the workspace"));

  // A saw the speed limit cannot allow.
  PlannerOptions slow;
  slow.max_linear_speed_m_s = 0.06;
  CHECK_THROWS_WITH(PlanCutTrajectory(cucumber, Spec(CutStyle::kSaw, CutState::kMiddle, "cucumber"),
                                      StartPose(), slow, 1),
                    Catch::Contains("saw_amplitude_m"));

  CutSpec bad_ratio = Spec(CutStyle::kNormal, CutState::kRatio, "cucumber");
  bad_ratio.ratio = 0.95;
  CHECK_THROWS_AS(PlanCutTrajectory(cucumber, bad_ratio, StartPose(), PlannerOptions{}, 1),
                  TaskError);
  // Options a request could send that would make plans last for days or turn into NaN.
  PlannerOptions crawl;
  crawl.cut_speed_m_s = {1e-9, 1e-9};
  CHECK_THROWS_WITH(ValidatePlannerOptions(crawl), Catch::Contains("cut_speed_m_s"));
  PlannerOptions tiny_limit;
  tiny_limit.max_linear_speed_m_s = 1e-300;
  CHECK_THROWS_WITH(ValidatePlannerOptions(tiny_limit), Catch::Contains("max_linear_speed_m_s"));
  PlannerOptions not_a_number;
  not_a_number.max_angular_speed_rad_s = std::nan("");
  CHECK_THROWS_WITH(ValidatePlannerOptions(not_a_number), Catch::Contains("max_angular_speed_rad_s"));
  PlannerOptions slowest;
  slowest.cut_speed_m_s = {1e-3, 1e-3};
  slowest.saw_cut_speed_m_s = {1e-3, 1e-3};
  slowest.max_linear_speed_m_s = 0.01;
  slowest.max_angular_speed_rad_s = 0.05;
  slowest.approach_clearance_m = 0.5;
  CutSpec five_way = Spec(CutStyle::kNormal, CutState::kSplit, "cucumber");
  five_way.split_pieces = 5;
  CHECK_THROWS_WITH(PlanCutTrajectory(cucumber, five_way, StartPose(), slowest, 1),
                    Catch::Contains("over the 600 s limit"));

  CHECK_THROWS_WITH(PlanCutTrajectory(cucumber, Spec(CutStyle::kNormal, CutState::kMiddle, "apple"),
                                      StartPose(), PlannerOptions{}, 1),
                    Catch::Contains("is a cucumber, but the task cuts the apple"));
  Eigen::Isometry3d skewed = StartPose();
  skewed.linear()(0, 1) = 0.5;
  CHECK_THROWS_WITH(PlanCutTrajectory(cucumber, middle, skewed, PlannerOptions{}, 1),
                    Catch::Contains("start TCP pose"));
}

}  // namespace
}  // namespace culinarycut::task
