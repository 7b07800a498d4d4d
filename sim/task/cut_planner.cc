#include "sim/task/cut_planner.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <random>
#include <sstream>

#include "sim/core/pose.h"
#include "sim/task/time_scaling.h"
#include "sim/task/trajectory_segment.h"

namespace culinarycut::task {

struct CutTrajectory::Segment : TrajectorySegment {};

namespace {

// Knife of assets/panda: the TCP is the middle of the 0.20 m cutting edge.
constexpr double kBladeLength_m = 0.20;
constexpr double kTcpToTip_m = 0.10;
// Planned peak speeds stay this fraction under the limits (the saw bound is also conservative).
constexpr double kLimitMargin = 0.9;
constexpr double kMinMoveDuration_s = 0.2;  // a tiny move still gets a gentle profile
constexpr double kCutRamp_s = 0.1;          // speed-up and slow-down at the ends of a cut
constexpr double kGuillotineTipMargin_m = 0.01;    // tip at least this far beyond the far side
constexpr double kGuillotineHeelMargin_m = 0.005;  // heel beyond the near side at the cut end
constexpr double kMaxGuillotinePitch_rad = 1.22;   // 70 deg; steeper and the handle stands up
constexpr double kMaxBiasAngle_rad = 1.22;
// |cos| between the blade and the base->object direction below this: ask the start pose instead.
constexpr double kBladeSignTie = 0.05;
constexpr double kCheckStep_s = 1e-3;  // the plan is checked at least at 1 kHz
constexpr double kMinCutSpeed_m_s = 1e-3;      // slower is not cutting, and plans would last hours
constexpr double kMinLinearSpeed_m_s = 0.01;
constexpr double kMaxPlanDuration_s = 600.0;   // longer plans are a mistake in the options
constexpr double kLimitTolerance = 1e-9;
constexpr double kTwoPi = 6.283185307179586;

std::string Format(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string Format(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

void ValidateRange(const SampledRange& range, const std::string& name, double lowest,
                   double highest) {
  if (!std::isfinite(range.min) || !std::isfinite(range.max)) {
    throw TaskError("planner option " + name + " is not finite");
  }
  if (range.min > range.max) {
    throw TaskError("planner option " + name + " is an inverted range: min " + Format(range.min) +
                    " > max " + Format(range.max));
  }
  if (range.min < lowest || range.max > highest) {
    throw TaskError("planner option " + name + " [" + Format(range.min) + ", " +
                    Format(range.max) + "] must lie within [" + Format(lowest) + ", " +
                    Format(highest) + "]");
  }
}

// NaN fails the comparison and is refused with the rest.
void ValidateWithin(double value, const std::string& name, double lowest, double highest) {
  if (!(value >= lowest && value <= highest)) {
    throw TaskError("planner option " + name + " must lie within [" + Format(lowest) + ", " +
                    Format(highest) + "], got " + Format(value));
  }
}

// Portable uniform draw in [0, 1): std::uniform_real_distribution differs between libraries.
double Uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

double Pick(const SampledRange& range, double u) { return range.min + u * (range.max - range.min); }

Eigen::Isometry3d MakePose(const Eigen::Vector3d& position_m, const Eigen::Matrix3d& rotation) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = position_m;
  return pose;
}

Eigen::Isometry3d AtHeight(Eigen::Isometry3d pose, double z_m) {
  pose.translation().z() = z_m;
  return pose;
}

// Knife orientation with the blade x along `tip_direction` and the edge pointing along
// `edge_direction` (perpendicular to it); the blade normal completes the right-handed frame.
Eigen::Matrix3d KnifeRotation(const Eigen::Vector3d& tip_direction,
                              const Eigen::Vector3d& edge_direction) {
  Eigen::Matrix3d rotation;
  rotation.col(0) = tip_direction;
  rotation.col(2) = edge_direction;
  rotation.col(1) = edge_direction.cross(tip_direction);
  return rotation;
}

// Heights shared by every cut of the plan (world z, m).
struct Heights {
  double top_z = 0.0;
  double bottom_z = 0.0;
  double clearance_z = 0.0;  // TCP height for approach, transfer and retreat
  double cut_start_z = 0.0;  // edge height where the slow cut begins
  double cut_end_z = 0.0;    // edge height where it ends
};

// The poses of one cut. Line cuts move along a straight line; the guillotine pivots.
struct CutPoses {
  Eigen::Isometry3d above;  // ready to descend, at the clearance height
  Eigen::Isometry3d cut_start;
  Eigen::Isometry3d cut_end;
  Eigen::Isometry3d after;  // retreated to the clearance height
  bool pivot = false;
  Eigen::Vector3d pivot_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d pivot_rotation_rad = Eigen::Vector3d::Zero();
};

// Horizontal blade direction (tip) perpendicular to the long axis: pointing away from the robot
// base so the handle is nearer the robot; when the blade runs across that direction (within
// kBladeSignTie), the sign closer to the start TCP's x axis; +z x u if that is a tie too.
Eigen::Vector3d TipDirection(const Eigen::Vector3d& along, const Eigen::Vector3d& object_centre_m,
                             const Eigen::Isometry3d& start_tcp_pose) {
  const Eigen::Vector3d tip = Eigen::Vector3d::UnitZ().cross(along).normalized();
  Eigen::Vector3d outward(object_centre_m.x(), object_centre_m.y(), 0.0);
  double score = outward.norm() > 1e-9 ? tip.dot(outward.normalized()) : 0.0;
  if (std::abs(score) < kBladeSignTie) {
    Eigen::Vector3d start_x = start_tcp_pose.linear().col(0);
    start_x.z() = 0.0;
    score = tip.dot(start_x);
  }
  return score < 0.0 ? Eigen::Vector3d(-tip) : tip;
}

// Normal, saw (tilt 0) and bias cuts: the TCP runs along the blade's edge direction on a line
// through the target point p, so the blade plane always contains p. Bias tilts the edge
// direction towards +along (the robot's right) by `tilt_rad`.
CutPoses LineCutPoses(const Eigen::Vector3d& p, const Eigen::Vector3d& along,
                      const Eigen::Vector3d& tip_direction, double tilt_rad,
                      const Heights& heights) {
  const Eigen::Vector3d edge_direction =
      std::sin(tilt_rad) * along - std::cos(tilt_rad) * Eigen::Vector3d::UnitZ();
  const Eigen::Matrix3d rotation = KnifeRotation(tip_direction, edge_direction);
  const auto at_height = [&](double z_m) {
    return MakePose(p + (p.z() - z_m) / std::cos(tilt_rad) * edge_direction, rotation);
  };
  CutPoses poses;
  poses.above = at_height(heights.clearance_z);
  poses.cut_start = at_height(heights.cut_start_z);
  poses.cut_end = at_height(heights.cut_end_z);
  poses.after = poses.above;
  return poses;
}

// Guillotine: the tip rests beyond the object's far side at the cut-end height; the knife starts
// pitched handle-up so that its edge passes cut_start_height above the object's top, then turns
// about the tip until the edge lies flat at the cut-end height. The blade stays in the vertical
// plane through p. `pitch_rad` comes in sampled and goes out as used: raised to the smallest pitch
// that clears a tall object.
CutPoses GuillotinePoses(const ObjectBox& box, const Eigen::Vector3d& p,
                         const Eigen::Vector3d& tip_direction, const Heights& heights,
                         double* pitch_rad) {
  const Eigen::Matrix3d& axes = box.pose.linear();
  double half_width_m = 0.0;
  for (int i = 0; i < 3; ++i) {
    half_width_m += 0.5 * box.extent_m[i] * std::abs(axes.col(i).dot(tip_direction));
  }
  const double width_m = 2.0 * half_width_m;
  const double max_width_m = kBladeLength_m - kGuillotineTipMargin_m - kGuillotineHeelMargin_m;
  if (width_m > max_width_m) {
    throw TaskError("guillotine cut: object '" + box.name + "' is " + Format(width_m) +
                    " m wide along the blade, but the " + Format(kBladeLength_m) +
                    " m blade covers at most " + Format(max_width_m) + " m with its margins");
  }
  const double rise_m = heights.cut_start_z - heights.cut_end_z;
  const double max_far_gap_m = kBladeLength_m - width_m - kGuillotineHeelMargin_m;
  *pitch_rad = std::max(*pitch_rad, std::atan2(rise_m, max_far_gap_m));
  if (*pitch_rad > kMaxGuillotinePitch_rad) {
    throw TaskError("guillotine cut: object '" + box.name + "' is too tall for the blade: the "
                    "edge would need a start pitch of " + Format(*pitch_rad) +
                    " rad (at most " + Format(kMaxGuillotinePitch_rad) + ") to clear its top");
  }
  const double far_gap_m = std::max(kGuillotineTipMargin_m, rise_m / std::tan(*pitch_rad));
  const double centre_offset_m = (box.pose.translation() - p).dot(tip_direction);
  Eigen::Vector3d tip_m = p + (centre_offset_m + half_width_m + far_gap_m) * tip_direction;
  tip_m.z() = heights.cut_end_z;

  // Turning by +pitch about this axis lowers the tip side and raises the handle side.
  const Eigen::Vector3d pitch_axis = Eigen::Vector3d::UnitZ().cross(tip_direction);
  const Eigen::Matrix3d flat = KnifeRotation(tip_direction, -Eigen::Vector3d::UnitZ());
  const Eigen::Matrix3d pitched = Eigen::AngleAxisd(*pitch_rad, pitch_axis) * flat;

  CutPoses poses;
  poses.cut_start = MakePose(tip_m - kTcpToTip_m * pitched.col(0), pitched);
  poses.cut_end = MakePose(tip_m - kTcpToTip_m * tip_direction, flat);
  poses.above = AtHeight(poses.cut_start,
                         std::max(heights.clearance_z, poses.cut_start.translation().z()));
  poses.after = AtHeight(poses.cut_end, heights.clearance_z);
  poses.pivot = true;
  poses.pivot_m = tip_m;
  poses.pivot_rotation_rad = -*pitch_rad * pitch_axis;
  return poses;
}

// Rest-to-rest minimum-jerk move, as short as the speed limits allow.
TimeScaling MoveScaling(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to,
                        const PlannerOptions& options) {
  const double distance_m = (to.translation() - from.translation()).norm();
  const double angle_rad = AngleBetween(from.linear(), to.linear());
  return QuinticScaling(std::max(
      {kMinMoveDuration_s,
       kQuinticPeakRate * distance_m / (kLimitMargin * options.max_linear_speed_m_s),
       kQuinticPeakRate * angle_rad / (kLimitMargin * options.max_angular_speed_rad_s)}));
}

// Saw amplitude: drawn (with `u`) from the part of the range whose peak speed stays within the
// limit. Peak TCP speed <= hypot(descent, A * (2 pi f + max envelope slope)).
double SawAmplitude(const PlannerOptions& options, double frequency_hz, double cut_speed_m_s,
                    double envelope_ramp_s, double u) {
  const double limit_m_s = kLimitMargin * options.max_linear_speed_m_s;
  const double lateral_m_s =
      std::sqrt(std::max(0.0, limit_m_s * limit_m_s - cut_speed_m_s * cut_speed_m_s));
  const double max_amplitude_m =
      lateral_m_s / (kTwoPi * frequency_hz + kSmoothStepMaxSlope / envelope_ramp_s);
  const SampledRange& range = options.saw_amplitude_m;
  if (max_amplitude_m < range.min) {
    throw TaskError("saw cut: at " + Format(frequency_hz) + " Hz and a descent of " +
                    Format(cut_speed_m_s) + " m/s, amplitudes above " + Format(max_amplitude_m) +
                    " m would exceed max_linear_speed_m_s " +
                    Format(options.max_linear_speed_m_s) + ", but saw_amplitude_m starts at " +
                    Format(range.min) + " m; lower saw_amplitude_m or saw_frequency_hz");
  }
  return Pick({range.min, std::min(range.max, max_amplitude_m)}, u);
}

std::string Where(const TrajectorySegment& segment, int cut_count) {
  std::string where = "the " + Name(segment.phase);
  if (segment.cut_index >= 0) {
    where += " of cut " + std::to_string(segment.cut_index + 1) + " of " +
             std::to_string(cut_count);
  }
  return where;
}

// Samples a segment at least at 1 kHz: workspace and speed limits. The speeds hold by
// construction; the check guards the construction.
void CheckSegment(const TrajectorySegment& segment, int cut_count, const PlannerOptions& options) {
  const double duration_s = segment.scaling.duration_s;
  const std::int64_t steps =
      std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(duration_s / kCheckStep_s)));
  for (std::int64_t k = 0; k <= steps; ++k) {
    const TrajectorySample sample = EvaluateSegment(segment, duration_s * k / steps);
    const Eigen::Vector3d& tcp_m = sample.tcp_pose.translation();
    // Written so that a NaN position or speed fails the check.
    if (!((tcp_m.array() >= options.workspace_min_m.array() - kLimitTolerance).all() &&
          (tcp_m.array() <= options.workspace_max_m.array() + kLimitTolerance).all())) {
      throw TaskError("the planned knife trajectory leaves the workspace: TCP at " +
                      Format(tcp_m) + " m during " + Where(segment, cut_count) + " (t = " +
                      Format(sample.time_s) + " s); workspace is " +
                      Format(options.workspace_min_m) + " to " + Format(options.workspace_max_m) +
                      " m");
    }
    const double speed_m_s = sample.linear_velocity_m_s.norm();
    const double turn_rad_s = sample.angular_velocity_rad_s.norm();
    if (!(speed_m_s <= options.max_linear_speed_m_s * (1.0 + kLimitTolerance) &&
          turn_rad_s <= options.max_angular_speed_rad_s * (1.0 + kLimitTolerance))) {
      throw TaskError("the planned knife trajectory exceeds the speed limits during " +
                      Where(segment, cut_count) + ": " + Format(speed_m_s) + " m/s, " +
                      Format(turn_rad_s) + " rad/s at t = " + Format(sample.time_s) + " s");
    }
  }
}

void ValidateStartPose(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d& rotation = pose.linear();
  if (!pose.matrix().allFinite() ||
      !(rotation.transpose() * rotation).isIdentity(1e-6) || rotation.determinant() < 0.0) {
    throw TaskError("the start TCP pose is not finite or its rotation is not a rotation");
  }
}

}  // namespace

std::string Name(SegmentPhase phase) {
  switch (phase) {
    case SegmentPhase::kApproach: return "approach";
    case SegmentPhase::kDescend: return "descend";
    case SegmentPhase::kCut: return "cut";
    case SegmentPhase::kRetreat: return "retreat";
    case SegmentPhase::kTransfer: return "transfer";
  }
  return "unknown";
}

void ValidatePlannerOptions(const PlannerOptions& options) {
  // Bounds keep every plan physically meaningful and its checking bounded in time.
  ValidateWithin(options.max_linear_speed_m_s, "max_linear_speed_m_s", kMinLinearSpeed_m_s, 2.0);
  ValidateWithin(options.max_angular_speed_rad_s, "max_angular_speed_rad_s", 0.05, 5.0);
  ValidateWithin(options.approach_clearance_m, "approach_clearance_m", 1e-3, 0.5);
  ValidateWithin(options.cut_end_below_bottom_m, "cut_end_below_bottom_m", 0.0, 0.05);
  if (!options.workspace_min_m.allFinite() || !options.workspace_max_m.allFinite() ||
      (options.workspace_min_m.array() >= options.workspace_max_m.array()).any()) {
    throw TaskError("planner option workspace_min_m must be finite and below workspace_max_m");
  }
  const double inf = std::numeric_limits<double>::infinity();
  ValidateRange(options.cut_start_height_m, "cut_start_height_m", 0.0,
                options.approach_clearance_m);
  ValidateRange(options.cut_speed_m_s, "cut_speed_m_s", kMinCutSpeed_m_s, options.max_linear_speed_m_s);
  ValidateRange(options.saw_cut_speed_m_s, "saw_cut_speed_m_s", kMinCutSpeed_m_s,
                options.max_linear_speed_m_s);
  ValidateRange(options.bias_angle_rad, "bias_angle_rad", 0.0, kMaxBiasAngle_rad);
  ValidateRange(options.saw_frequency_hz, "saw_frequency_hz", 0.0, inf);
  if (options.saw_frequency_hz.min <= 0.0) {
    throw TaskError("planner option saw_frequency_hz must be > 0, got min " +
                    Format(options.saw_frequency_hz.min));
  }
  ValidateRange(options.saw_amplitude_m, "saw_amplitude_m", 0.0, inf);
  ValidateRange(options.guillotine_start_pitch_rad, "guillotine_start_pitch_rad", 0.0,
                kMaxGuillotinePitch_rad);
  if (!options.workspace_min_m.allFinite() || !options.workspace_max_m.allFinite() ||
      (options.workspace_min_m.array() >= options.workspace_max_m.array()).any()) {
    throw TaskError("planner option workspace is empty or not finite: min " +
                    Format(options.workspace_min_m) + ", max " + Format(options.workspace_max_m));
  }
}

CutTrajectory::CutTrajectory() = default;
CutTrajectory::~CutTrajectory() = default;
CutTrajectory::CutTrajectory(const CutTrajectory&) = default;
CutTrajectory& CutTrajectory::operator=(const CutTrajectory&) = default;
CutTrajectory::CutTrajectory(CutTrajectory&&) noexcept = default;
CutTrajectory& CutTrajectory::operator=(CutTrajectory&&) noexcept = default;

double CutTrajectory::duration_s() const {
  return segments_.empty() ? 0.0 : segments_.back().end_time_s();
}

TrajectorySample CutTrajectory::Sample(double time_s) const {
  TrajectorySample sample;
  sample.time_s = time_s;
  if (segments_.empty()) return sample;
  if (time_s <= 0.0 || time_s >= duration_s()) {
    // Outside the plan the knife rests at the first or last pose.
    const auto& segment = time_s <= 0.0 ? segments_.front() : segments_.back();
    sample.tcp_pose = time_s <= 0.0 ? EvaluateSegment(segment, 0.0).tcp_pose : EndPose(segment);
    return sample;
  }
  const auto next = std::upper_bound(
      segments_.begin(), segments_.end(), time_s,
      [](double t, const Segment& segment) { return t < segment.start_time_s; });
  const Segment& segment = *std::prev(next);
  sample = EvaluateSegment(segment, time_s - segment.start_time_s);
  sample.time_s = time_s;
  return sample;
}

std::vector<TrajectorySample> CutTrajectory::SampleUniform(double rate_hz) const {
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) {
    throw TaskError("SampleUniform needs a finite rate > 0 Hz, got " + Format(rate_hz));
  }
  const double end_s = duration_s();
  const auto count = static_cast<long>(std::floor(end_s * rate_hz + 1e-9));
  std::vector<TrajectorySample> samples;
  samples.reserve(count + 2);
  for (long k = 0; k <= count; ++k) samples.push_back(Sample(k / rate_hz));
  // The end itself, unless the last uniform sample already fell on it.
  if (end_s - samples.back().time_s > 1e-9) samples.push_back(Sample(end_s));
  return samples;
}

SegmentPhase CutTrajectory::PhaseAt(double time_s) const {
  if (segments_.empty()) return SegmentPhase::kApproach;
  for (const auto& segment : segments_) {
    if (time_s < segment.end_time_s()) return segment.phase;
  }
  return segments_.back().phase;
}

std::vector<CutTrajectory::PhaseSpan> CutTrajectory::Phases() const {
  std::vector<PhaseSpan> spans;
  for (const auto& segment : segments_) {
    spans.push_back({segment.phase, segment.start_time_s, segment.end_time_s()});
  }
  return spans;
}

CutTrajectory PlanCutTrajectory(const ObjectBox& target, const CutSpec& spec,
                                const Eigen::Isometry3d& start_tcp_pose,
                                const PlannerOptions& options, std::uint64_t seed) {
  ValidateObjectBox(target);
  ValidateCutSpec(spec);
  ValidatePlannerOptions(options);
  ValidateStartPose(start_tcp_pose);
  if (target.food != spec.target_object) {
    throw TaskError("object '" + target.name + "' is a " + target.food + ", but the task cuts the " +
                    spec.target_object);
  }

  // Every draw happens in this order whatever the style, so a seed means the same numbers.
  std::mt19937_64 rng(seed);
  const double u_height = Uniform01(rng);
  const double u_speed = Uniform01(rng);
  const double u_bias = Uniform01(rng);
  const double u_frequency = Uniform01(rng);
  const double u_amplitude = Uniform01(rng);
  const double u_pitch = Uniform01(rng);

  CutTrajectory plan;
  plan.spec_ = spec;
  SampledCutParameters& parameters = plan.parameters_;
  parameters.cut_start_height_m = Pick(options.cut_start_height_m, u_height);
  parameters.cut_speed_m_s = Pick(
      spec.style == CutStyle::kSaw ? options.saw_cut_speed_m_s : options.cut_speed_m_s, u_speed);

  Heights heights;
  heights.top_z = TopZ(target);
  heights.bottom_z = BottomZ(target);
  heights.clearance_z = heights.top_z + options.approach_clearance_m;
  heights.cut_start_z = heights.top_z + parameters.cut_start_height_m;
  heights.cut_end_z = heights.bottom_z - options.cut_end_below_bottom_m;

  const LongAxis axis = LongAxisOf(target);
  // Cut planes are vertical (bias: tilted from vertical) across the horizontal long axis.
  const Eigen::Vector3d along =
      Eigen::Vector3d(axis.direction.x(), axis.direction.y(), 0.0).normalized();
  const Eigen::Vector3d tip_direction =
      TipDirection(along, target.pose.translation(), start_tcp_pose);

  double tilt_rad = 0.0;
  SawOscillation saw;
  TimeScaling line_cut_scaling;
  if (spec.style == CutStyle::kBias) {
    parameters.bias_angle_rad = Pick(options.bias_angle_rad, u_bias);
    tilt_rad = parameters.bias_angle_rad;
  }
  if (spec.style == CutStyle::kSaw) {
    parameters.saw_frequency_hz = Pick(options.saw_frequency_hz, u_frequency);
    line_cut_scaling = CruiseScaling(heights.cut_start_z - heights.cut_end_z,
                                     parameters.cut_speed_m_s, kCutRamp_s);
    saw.axis = tip_direction;
    saw.frequency_hz = parameters.saw_frequency_hz;
    // One stroke to swell to full amplitude, one to fade out; never overlapping.
    saw.envelope_ramp_s =
        std::min(1.0 / saw.frequency_hz, 0.5 * line_cut_scaling.duration_s);
    saw.amplitude_m = SawAmplitude(options, saw.frequency_hz, parameters.cut_speed_m_s,
                                   saw.envelope_ramp_s, u_amplitude);
    parameters.saw_amplitude_m = saw.amplitude_m;
  }

  std::vector<CutPoses> cuts;
  double pitch_rad = Pick(options.guillotine_start_pitch_rad, u_pitch);
  for (const double fraction : TargetFractionsFromLeft(spec)) {
    const Eigen::Vector3d p = PointAtFraction(axis, fraction);
    cuts.push_back(spec.style == CutStyle::kGuillotine
                       ? GuillotinePoses(target, p, tip_direction, heights, &pitch_rad)
                       : LineCutPoses(p, along, tip_direction, tilt_rad, heights));
    PlannedCut planned;
    planned.fraction_from_left = fraction;
    planned.target_point_m = p;
    planned.blade_plane_normal = cuts.back().cut_start.linear().col(1);
    // The plane the cut should lie in, its normal oriented left -> right.
    planned.target_plane_normal = planned.blade_plane_normal.dot(along) < 0.0
                                      ? Eigen::Vector3d(-planned.blade_plane_normal)
                                      : planned.blade_plane_normal;
    plan.cuts_.push_back(planned);
  }
  if (spec.style == CutStyle::kGuillotine) parameters.guillotine_start_pitch_rad = pitch_rad;

  double time_s = 0.0;
  const auto add = [&](TrajectorySegment segment) {
    segment.start_time_s = time_s;
    time_s = segment.end_time_s();
    plan.segments_.push_back(CutTrajectory::Segment{segment});
  };
  const auto move = [&](SegmentPhase phase, int cut, const Eigen::Isometry3d& from,
                        const Eigen::Isometry3d& to) {
    add(LineSegment(phase, cut, from, to, MoveScaling(from, to, options)));
  };

  // Approach: rise first when starting below the clearance height, so the move runs above.
  Eigen::Isometry3d here = start_tcp_pose;
  if (here.translation().z() < cuts.front().above.translation().z()) {
    const Eigen::Isometry3d lifted = AtHeight(here, cuts.front().above.translation().z());
    move(SegmentPhase::kApproach, -1, here, lifted);
    here = lifted;
  }
  move(SegmentPhase::kApproach, -1, here, cuts.front().above);

  const double pivot_rate_rad_s =
      std::min(parameters.cut_speed_m_s / kTcpToTip_m,
               kLimitMargin * options.max_angular_speed_rad_s);
  for (int i = 0; i < static_cast<int>(cuts.size()); ++i) {
    const CutPoses& cut = cuts[i];
    if (i > 0) move(SegmentPhase::kTransfer, i, cuts[i - 1].after, cut.above);
    move(SegmentPhase::kDescend, i, cut.above, cut.cut_start);
    plan.cuts_[i].start_time_s = time_s;
    if (cut.pivot) {
      // The TCP, kTcpToTip_m from the tip, moves at the sampled cut speed.
      add(PivotSegment(SegmentPhase::kCut, i, cut.cut_start, cut.pivot_m, cut.pivot_rotation_rad,
                       CruiseScaling(cut.pivot_rotation_rad.norm(), pivot_rate_rad_s,
                                     kCutRamp_s)));
    } else {
      const double distance_m = (cut.cut_end.translation() - cut.cut_start.translation()).norm();
      TrajectorySegment segment =
          LineSegment(SegmentPhase::kCut, i, cut.cut_start, cut.cut_end,
                      CruiseScaling(distance_m, parameters.cut_speed_m_s, kCutRamp_s));
      segment.saw = saw;
      add(segment);
    }
    plan.cuts_[i].end_time_s = time_s;
    move(SegmentPhase::kRetreat, i, cut.cut_end, cut.after);
  }

  if (!(time_s <= kMaxPlanDuration_s)) {
    throw TaskError("the plan would last " + Format(time_s) + " s, over the " +
                    Format(kMaxPlanDuration_s) + " s limit; raise the cut and speed options");
  }
  for (const auto& segment : plan.segments_) {
    CheckSegment(segment, static_cast<int>(cuts.size()), options);
  }
  return plan;
}

}  // namespace culinarycut::task
