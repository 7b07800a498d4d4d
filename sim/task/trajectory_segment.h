// One piece of a planned knife trajectory: a straight TCP move or a rotation about a fixed point,
// run by a time scaling, with an optional saw oscillation on top. Internal to the cut planner.
#pragma once

#include <Eigen/Geometry>

#include "sim/task/cut_planner.h"
#include "sim/task/time_scaling.h"

namespace culinarycut::task {

// Back-and-forth along `axis`: amplitude_m * envelope(t) * sin(2 pi f t), where the envelope
// rises and falls over `envelope_ramp_s` (smoothstep) so the segment still starts and ends at rest.
struct SawOscillation {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  // unit, world frame
  double amplitude_m = 0.0;
  double frequency_hz = 0.0;
  double envelope_ramp_s = 0.0;
};

struct TrajectorySegment {
  // kLine: the TCP travels start -> end in a straight line while turning by s * rotation_vector.
  // kPivot: the whole knife turns by s * rotation_vector about pivot_m (the TCP follows an arc).
  enum class Path { kLine, kPivot };

  SegmentPhase phase = SegmentPhase::kApproach;
  int cut_index = -1;  // the cut this segment serves; -1 before the first
  double start_time_s = 0.0;
  TimeScaling scaling;
  Path path = Path::kLine;
  Eigen::Vector3d start_position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d end_position_m = Eigen::Vector3d::Zero();  // kLine only
  Eigen::Vector3d pivot_m = Eigen::Vector3d::Zero();         // kPivot only
  Eigen::Matrix3d start_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d rotation_vector_rad = Eigen::Vector3d::Zero();  // whole turn, world frame
  SawOscillation saw;  // none while amplitude_m == 0

  double end_time_s() const { return start_time_s + scaling.duration_s; }
};

// Straight move between two poses (the orientation turns about one fixed world axis).
TrajectorySegment LineSegment(SegmentPhase phase, int cut_index, const Eigen::Isometry3d& from,
                              const Eigen::Isometry3d& to, const TimeScaling& scaling);

// Rigid turn of the knife at `from` by `rotation_vector_rad` (world frame) about `pivot_m`.
TrajectorySegment PivotSegment(SegmentPhase phase, int cut_index, const Eigen::Isometry3d& from,
                               const Eigen::Vector3d& pivot_m,
                               const Eigen::Vector3d& rotation_vector_rad,
                               const TimeScaling& scaling);

// Pose at the segment's end (s = 1, no oscillation left).
Eigen::Isometry3d EndPose(const TrajectorySegment& segment);

// TCP state at `local_time_s` seconds into the segment (clamped to the segment), with analytic
// velocities; time_s of the result is start_time_s + local_time_s.
TrajectorySample EvaluateSegment(const TrajectorySegment& segment, double local_time_s);

}  // namespace culinarycut::task
