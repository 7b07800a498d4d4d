// The cut-trajectory planner: from an object's oriented box and a CutSpec, a time-parametrised
// knife TCP trajectory for each cut style (paper, "Trajectory Augmentation" and supplement
// "Trajectory Visualization"). This is what the scripted oracle and dataset augmentation execute.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sim/task/cut_spec.h"
#include "sim/task/object_box.h"

namespace culinarycut::task {

// A closed interval the planner samples uniformly from (same seed -> same sample).
struct SampledRange {
  double min = 0.0;
  double max = 0.0;
};

// Defaults suit the Panda with the knife of assets/panda (TCP = middle of the cutting edge; TCP
// frame: x along the blade to the tip, y the blade normal, z from the spine to the edge).
struct PlannerOptions {
  double approach_clearance_m = 0.08;        // TCP height above the object's top for transfers
  SampledRange cut_start_height_m{0.01, 0.03};  // above the object's top where the slow cut begins
  SampledRange cut_speed_m_s{0.02, 0.05};    // knife speed through the food
  // Saw cuts descend slower so that the knife makes several strokes (about 3-18 through 4 cm).
  SampledRange saw_cut_speed_m_s{0.008, 0.015};
  double cut_end_below_bottom_m = 0.001;     // edge ends this far below the object's bottom
  double max_linear_speed_m_s = 0.25;        // TCP speed limit for every segment
  double max_angular_speed_rad_s = 1.0;      // TCP angular speed limit for every segment
  SampledRange bias_angle_rad{0.35, 0.61};   // blade tilt from vertical for bias cuts (20-35 deg)
  SampledRange saw_frequency_hz{1.0, 2.0};   // back-and-forth strokes per second
  SampledRange saw_amplitude_m{0.01, 0.025}; // stroke half-length along the blade
  SampledRange guillotine_start_pitch_rad{0.35, 0.52};  // blade tilt about the tip at the start
  // Workspace the TCP must stay in (world frame, m); a plan that leaves it is refused.
  Eigen::Vector3d workspace_min_m{0.15, -0.6, 0.0};
  Eigen::Vector3d workspace_max_m{0.85, 0.6, 0.8};
};

// Throws TaskError naming the bad field (empty or inverted range, non-positive speed, ...).
void ValidatePlannerOptions(const PlannerOptions& options);

// Knife TCP state on the trajectory, world frame.
struct TrajectorySample {
  double time_s = 0.0;
  Eigen::Isometry3d tcp_pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d linear_velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_rad_s = Eigen::Vector3d::Zero();
};

// What a part of the trajectory is for.
enum class SegmentPhase { kApproach, kDescend, kCut, kRetreat, kTransfer };
std::string Name(SegmentPhase phase);

// One cut of the plan and the plane the blade sweeps.
struct PlannedCut {
  double fraction_from_left = 0.0;     // target position along the long axis
  Eigen::Vector3d target_point_m;      // that position on the long axis (world)
  Eigen::Vector3d target_plane_normal; // unit; the plane the cut should lie in
  Eigen::Vector3d blade_plane_normal;  // unit; the plane the planned blade sweeps
  double start_time_s = 0.0;           // the cut phase (knife in the food) begins ...
  double end_time_s = 0.0;             // ... and ends
};

// The parameters the planner drew for this plan.
struct SampledCutParameters {
  double cut_start_height_m = 0.0;
  double cut_speed_m_s = 0.0;
  double bias_angle_rad = 0.0;       // bias only
  double saw_frequency_hz = 0.0;     // saw only
  // Saw only: drawn from the part of saw_amplitude_m whose peak TCP speed stays under the limit
  // (a high frequency narrows it; no room at all is a TaskError).
  double saw_amplitude_m = 0.0;
  // Guillotine only, as used: raised above the sampled pitch when the object is too tall for the
  // edge to clear its top with the tip inside the blade's reach.
  double guillotine_start_pitch_rad = 0.0;
};

// A planned knife trajectory: a chain of segments, continuous in pose and velocity.
class CutTrajectory {
 public:
  struct Segment;  // defined in cut_planner.cc (a TrajectorySegment, sim/task/trajectory_segment.h)
  CutTrajectory();
  ~CutTrajectory();
  CutTrajectory(const CutTrajectory&);
  CutTrajectory& operator=(const CutTrajectory&);
  CutTrajectory(CutTrajectory&&) noexcept;
  CutTrajectory& operator=(CutTrajectory&&) noexcept;

  double duration_s() const;
  // TCP state at `time_s`; times before 0 or after the end hold the first or last pose at rest.
  TrajectorySample Sample(double time_s) const;
  // Samples at 0, 1/rate, 2/rate, ... and at the end itself (so the last step may be shorter).
  std::vector<TrajectorySample> SampleUniform(double rate_hz) const;
  // The phase at `time_s` (the last segment's phase after the end).
  SegmentPhase PhaseAt(double time_s) const;
  // (phase, start time, end time) of every segment, in order.
  struct PhaseSpan {
    SegmentPhase phase;
    double start_time_s;
    double end_time_s;
  };
  std::vector<PhaseSpan> Phases() const;

  const std::vector<PlannedCut>& cuts() const { return cuts_; }
  const SampledCutParameters& parameters() const { return parameters_; }
  const CutSpec& spec() const { return spec_; }

 private:
  friend CutTrajectory PlanCutTrajectory(const ObjectBox&, const CutSpec&, const Eigen::Isometry3d&,
                                         const PlannerOptions&, std::uint64_t);
  std::vector<Segment> segments_;
  std::vector<PlannedCut> cuts_;
  SampledCutParameters parameters_;
  CutSpec spec_;
};

// Plans the cuts of `spec` on `target`, starting from the TCP pose `start_tcp_pose` at rest.
// The blade stands across the long axis with its tip pointing away from the robot base (handle
// nearer the robot); if the blade runs across that direction (within 3 deg), the sign nearer the
// start TCP's x axis. Every move is rest-to-rest minimum-jerk at <= 90% of the speed limits; a cut
// runs at the sampled speed between 0.1 s ramps, from the edge at cut_start_height above the top to
// cut_end_below_bottom under the bottom. Normal: vertical descent. Bias: the blade rolled about its
// edge by the sampled angle, the TCP descending along the tilted plane with a drift towards the
// robot's right; the plane meets the long axis at the target. Guillotine: the tip rests beyond the
// object's far side at the cut-end height, the knife starts pitched handle-up so the edge clears
// the top by cut_start_height, then turns about the tip (TCP at the cut speed) until the edge lies
// flat. Saw: back and forth along the blade at the sampled frequency, swelling and fading over one
// stroke, while descending. Every cut retreats along the blade plane to approach_clearance above
// the top; splits cut left to right, transferring between cuts. Draws come from a local
// std::mt19937_64(seed) in a fixed order. Throws TaskError when the object is too wide or tall for
// the blade (guillotine), the saw cannot stay under the speed limit, the plan leaves the workspace
// (naming the phase and point), or the inputs are invalid.
CutTrajectory PlanCutTrajectory(const ObjectBox& target, const CutSpec& spec,
                                const Eigen::Isometry3d& start_tcp_pose,
                                const PlannerOptions& options, std::uint64_t seed);

}  // namespace culinarycut::task
