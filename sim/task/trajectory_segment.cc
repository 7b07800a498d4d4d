#include "sim/task/trajectory_segment.h"

#include <algorithm>
#include <cmath>

#include "sim/core/pose.h"

namespace culinarycut::task {
namespace {

constexpr double kTwoPi = 6.283185307179586;

// Offset and velocity of the saw oscillation at local time t.
void AddOscillation(const SawOscillation& saw, double duration_s, double t_s,
                    Eigen::Vector3d* position_m, Eigen::Vector3d* velocity_m_s) {
  if (saw.amplitude_m <= 0.0) return;
  // Envelope = rise(t) * fall(T - t): zero with zero slope at both ends, 1 in between.
  const double ramp = saw.envelope_ramp_s;
  double envelope = 1.0;
  double envelope_rate = 0.0;
  if (ramp > 0.0) {
    const double rise = SmoothStep(t_s / ramp);
    const double fall = SmoothStep((duration_s - t_s) / ramp);
    envelope = rise * fall;
    envelope_rate = (SmoothStepSlope(t_s / ramp) * fall -
                     rise * SmoothStepSlope((duration_s - t_s) / ramp)) / ramp;
  }
  const double omega = kTwoPi * saw.frequency_hz;
  const double phase = omega * t_s;
  *position_m += saw.amplitude_m * envelope * std::sin(phase) * saw.axis;
  *velocity_m_s += saw.amplitude_m *
                   (envelope_rate * std::sin(phase) + envelope * omega * std::cos(phase)) *
                   saw.axis;
}

}  // namespace

TrajectorySegment LineSegment(SegmentPhase phase, int cut_index, const Eigen::Isometry3d& from,
                              const Eigen::Isometry3d& to, const TimeScaling& scaling) {
  TrajectorySegment segment;
  segment.phase = phase;
  segment.cut_index = cut_index;
  segment.scaling = scaling;
  segment.path = TrajectorySegment::Path::kLine;
  segment.start_position_m = from.translation();
  segment.end_position_m = to.translation();
  segment.start_rotation = from.linear();
  segment.rotation_vector_rad = OrientationError(from.linear(), to.linear());
  return segment;
}

TrajectorySegment PivotSegment(SegmentPhase phase, int cut_index, const Eigen::Isometry3d& from,
                               const Eigen::Vector3d& pivot_m,
                               const Eigen::Vector3d& rotation_vector_rad,
                               const TimeScaling& scaling) {
  TrajectorySegment segment;
  segment.phase = phase;
  segment.cut_index = cut_index;
  segment.scaling = scaling;
  segment.path = TrajectorySegment::Path::kPivot;
  segment.start_position_m = from.translation();
  segment.pivot_m = pivot_m;
  segment.start_rotation = from.linear();
  segment.rotation_vector_rad = rotation_vector_rad;
  return segment;
}

Eigen::Isometry3d EndPose(const TrajectorySegment& segment) {
  return EvaluateSegment(segment, segment.scaling.duration_s).tcp_pose;
}

TrajectorySample EvaluateSegment(const TrajectorySegment& segment, double local_time_s) {
  const double t = std::clamp(local_time_s, 0.0, segment.scaling.duration_s);
  const Progress progress = Evaluate(segment.scaling, t);
  const Eigen::Matrix3d turn = RotationFromAxisAngle(progress.s * segment.rotation_vector_rad);

  TrajectorySample sample;
  sample.time_s = segment.start_time_s + t;
  sample.angular_velocity_rad_s = progress.rate_per_s * segment.rotation_vector_rad;
  Eigen::Vector3d position_m;
  if (segment.path == TrajectorySegment::Path::kLine) {
    const Eigen::Vector3d travel_m = segment.end_position_m - segment.start_position_m;
    position_m = segment.start_position_m + progress.s * travel_m;
    sample.linear_velocity_m_s = progress.rate_per_s * travel_m;
  } else {
    position_m = segment.pivot_m + turn * (segment.start_position_m - segment.pivot_m);
    sample.linear_velocity_m_s = sample.angular_velocity_rad_s.cross(position_m - segment.pivot_m);
  }
  AddOscillation(segment.saw, segment.scaling.duration_s, t, &position_m,
                 &sample.linear_velocity_m_s);
  sample.tcp_pose.linear() = turn * segment.start_rotation;
  sample.tcp_pose.translation() = position_m;
  return sample;
}

}  // namespace culinarycut::task
