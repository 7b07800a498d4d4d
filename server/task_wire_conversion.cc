#include "server/task_wire_conversion.h"

#include <cmath>

#include "sim/core/pose.h"

namespace culinarycut::server {
namespace {

Eigen::Vector3d Vector3FromWire(const google::protobuf::RepeatedField<double>& values,
                                const std::string& field) {
  if (values.size() != 3) {
    throw task::TaskError(field + " must have 3 values, got " + std::to_string(values.size()));
  }
  const Eigen::Vector3d vector(values[0], values[1], values[2]);
  if (!vector.allFinite()) throw task::TaskError(field + " has a non-finite value");
  return vector;
}

void Vector3ToWire(const Eigen::Vector3d& vector, google::protobuf::RepeatedField<double>* wire) {
  wire->Clear();
  for (int i = 0; i < 3; ++i) wire->Add(vector[i]);
}

// Overrides `range` when the message is set.
void RangeFromWire(bool present, const v1::Range& wire, task::SampledRange* range) {
  if (present) *range = {wire.min(), wire.max()};
}

}  // namespace

task::CutSpec CutSpecFromWire(const v1::CutSpec& wire) {
  task::CutSpec spec;
  spec.style = wire.style().empty() ? task::CutStyle::kNormal : task::CutStyleFromName(wire.style());
  spec.state = wire.state().empty() ? task::CutState::kMiddle : task::CutStateFromName(wire.state());
  spec.ratio = wire.ratio();
  spec.split_pieces = static_cast<int>(wire.split_pieces());
  spec.target_object = wire.target_object();
  spec.reference = wire.reference().empty() ? task::DirectionalReference::kNone
                                            : task::DirectionalReferenceFromName(wire.reference());
  if (spec.target_object.empty()) {
    throw task::TaskError("spec.target_object is empty; name the food to cut, e.g. \"cucumber\"");
  }
  task::ValidateCutSpec(spec);
  return spec;
}

void CutSpecToWire(const task::CutSpec& spec, v1::CutSpec* wire) {
  wire->set_style(task::Name(spec.style));
  wire->set_state(task::Name(spec.state));
  wire->set_ratio(spec.state == task::CutState::kRatio ? spec.ratio : 0.0);
  wire->set_split_pieces(spec.state == task::CutState::kSplit ? spec.split_pieces : 0);
  wire->set_target_object(spec.target_object);
  wire->set_reference(task::Name(spec.reference));
}

Eigen::Isometry3d PoseFromWire(const v1::Pose& wire, const std::string& field) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Vector3FromWire(wire.position(), field + ".position");
  if (wire.quaternion_size() != 4) {
    throw task::TaskError(field + ".quaternion must have 4 values [w, x, y, z], got " +
                          std::to_string(wire.quaternion_size()));
  }
  const std::optional<Eigen::Vector4d> wxyz = NormalizedQuaternion(
      {wire.quaternion(0), wire.quaternion(1), wire.quaternion(2), wire.quaternion(3)});
  if (!wxyz) throw task::TaskError(field + ".quaternion must be finite with a positive norm");
  pose.linear() = Eigen::Quaterniond((*wxyz)[0], (*wxyz)[1], (*wxyz)[2], (*wxyz)[3]).toRotationMatrix();
  return pose;
}

void PoseToWire(const Eigen::Isometry3d& pose, v1::Pose* wire) {
  Vector3ToWire(pose.translation(), wire->mutable_position());
  const Eigen::Quaterniond rotation(pose.linear());
  wire->clear_quaternion();
  for (double value : {rotation.w(), rotation.x(), rotation.y(), rotation.z()}) {
    wire->add_quaternion(value);
  }
}

task::ObjectBox ObjectBoxFromWire(const v1::ObjectBox& wire, const std::string& field) {
  task::ObjectBox box;
  box.name = wire.name().empty() ? wire.food() : wire.name();
  box.food = wire.food();
  if (box.food.empty()) throw task::TaskError(field + ".food is empty; name its food type");
  if (!wire.has_pose()) throw task::TaskError(field + ".pose is missing");
  box.pose = PoseFromWire(wire.pose(), field + ".pose");
  box.extent_m = Vector3FromWire(wire.extent_m(), field + ".extent_m");
  task::ValidateObjectBox(box);
  return box;
}

task::PlannerOptions PlannerOptionsFromWire(const v1::PlannerOptions& wire) {
  task::PlannerOptions options;
  if (wire.has_approach_clearance_m()) options.approach_clearance_m = wire.approach_clearance_m().value();
  RangeFromWire(wire.has_cut_start_height_m(), wire.cut_start_height_m(), &options.cut_start_height_m);
  RangeFromWire(wire.has_cut_speed_m_s(), wire.cut_speed_m_s(), &options.cut_speed_m_s);
  RangeFromWire(wire.has_saw_cut_speed_m_s(), wire.saw_cut_speed_m_s(), &options.saw_cut_speed_m_s);
  if (wire.has_cut_end_below_bottom_m()) {
    options.cut_end_below_bottom_m = wire.cut_end_below_bottom_m().value();
  }
  if (wire.has_max_linear_speed_m_s()) options.max_linear_speed_m_s = wire.max_linear_speed_m_s().value();
  if (wire.has_max_angular_speed_rad_s()) {
    options.max_angular_speed_rad_s = wire.max_angular_speed_rad_s().value();
  }
  RangeFromWire(wire.has_bias_angle_rad(), wire.bias_angle_rad(), &options.bias_angle_rad);
  RangeFromWire(wire.has_saw_frequency_hz(), wire.saw_frequency_hz(), &options.saw_frequency_hz);
  RangeFromWire(wire.has_saw_amplitude_m(), wire.saw_amplitude_m(), &options.saw_amplitude_m);
  RangeFromWire(wire.has_guillotine_start_pitch_rad(), wire.guillotine_start_pitch_rad(),
                &options.guillotine_start_pitch_rad);
  task::ValidatePlannerOptions(options);
  return options;
}

task::SuccessTolerances TolerancesFromWire(const v1::SuccessTolerances& wire) {
  task::SuccessTolerances tolerances;
  if (wire.has_position_fraction()) tolerances.position_fraction = wire.position_fraction().value();
  if (wire.has_angle_rad()) tolerances.angle_rad = wire.angle_rad().value();
  if (wire.has_bias_rad()) {
    tolerances.bias_min_rad = wire.bias_rad().min();
    tolerances.bias_max_rad = wire.bias_rad().max();
  }
  tolerances.allow_extra_cuts = wire.allow_extra_cuts();
  task::ValidateTolerances(tolerances);
  return tolerances;
}

task::MeasuredCut MeasuredCutFromWire(const v1::MeasuredCut& wire, const std::string& field) {
  task::MeasuredCut cut;
  cut.object_name = wire.object_name();
  if (cut.object_name.empty()) throw task::TaskError(field + ".object_name is empty");
  cut.plane_point_m = Vector3FromWire(wire.plane_point_m(), field + ".plane_point_m");
  if (wire.plane_normal_size() > 0) {
    const Eigen::Vector3d normal = Vector3FromWire(wire.plane_normal(), field + ".plane_normal");
    if (normal.norm() == 0.0) throw task::TaskError(field + ".plane_normal has zero length");
    cut.plane_normal = normal.normalized();
  }
  return cut;
}

void CutPlanToWire(const task::CutTrajectory& trajectory, const std::string& target_name,
                   double sample_rate_hz, v1::CutPlan* wire) {
  // Keeps a long plan at a high rate within gRPC's default 4 MB message limit (~130 B a sample).
  constexpr double kMaxSamples = 20000;
  if (trajectory.duration_s() * sample_rate_hz + 1 > kMaxSamples) {
    throw task::TaskError("the plan lasts " + std::to_string(trajectory.duration_s()) + " s; at " +
                          std::to_string(sample_rate_hz) + " Hz that is more than " +
                          std::to_string(static_cast<int>(kMaxSamples)) +
                          " samples; lower sample_rate_hz");
  }
  CutSpecToWire(trajectory.spec(), wire->mutable_spec());
  wire->set_target_name(target_name);
  wire->set_duration_s(trajectory.duration_s());
  for (const task::PlannedCut& cut : trajectory.cuts()) {
    v1::PlannedCut* out = wire->add_cuts();
    out->set_fraction_from_left(cut.fraction_from_left);
    Vector3ToWire(cut.target_point_m, out->mutable_target_point_m());
    Vector3ToWire(cut.target_plane_normal, out->mutable_target_plane_normal());
    Vector3ToWire(cut.blade_plane_normal, out->mutable_blade_plane_normal());
    out->set_start_time_s(cut.start_time_s);
    out->set_end_time_s(cut.end_time_s);
  }
  const task::SampledCutParameters& parameters = trajectory.parameters();
  v1::SampledCutParameters* out = wire->mutable_parameters();
  out->set_cut_start_height_m(parameters.cut_start_height_m);
  out->set_cut_speed_m_s(parameters.cut_speed_m_s);
  out->set_bias_angle_rad(parameters.bias_angle_rad);
  out->set_saw_frequency_hz(parameters.saw_frequency_hz);
  out->set_saw_amplitude_m(parameters.saw_amplitude_m);
  out->set_guillotine_start_pitch_rad(parameters.guillotine_start_pitch_rad);
  if (sample_rate_hz <= 0.0) return;
  for (const task::TrajectorySample& sample : trajectory.SampleUniform(sample_rate_hz)) {
    v1::TrajectorySample* out_sample = wire->add_samples();
    out_sample->set_time_s(sample.time_s);
    PoseToWire(sample.tcp_pose, out_sample->mutable_tcp_pose());
    Vector3ToWire(sample.linear_velocity_m_s, out_sample->mutable_linear_velocity_m_s());
    Vector3ToWire(sample.angular_velocity_rad_s, out_sample->mutable_angular_velocity_rad_s());
    out_sample->set_phase(task::Name(trajectory.PhaseAt(sample.time_s)));
  }
}

void TaskScoreToWire(const task::TaskScore& score, v1::TaskScore* wire) {
  wire->set_success(score.success);
  wire->set_cuts_required(score.cuts_required);
  wire->set_cuts_correct(score.cuts_correct);
  wire->set_cuts_within_position_tolerance(score.cuts_within_position_tolerance);
  wire->set_extra_cuts(score.extra_cuts);
  wire->set_wrong_object_cuts(score.wrong_object_cuts);
  for (const task::RequiredCutScore& required : score.required) {
    v1::RequiredCutScore* out = wire->add_required();
    out->set_target_fraction(required.target_fraction);
    out->set_placed(required.placed);
    out->set_measured_fraction(required.measured_fraction);
    out->set_position_error_fraction(required.position_error_fraction);
    out->set_angle_measured(required.angle_measured);
    out->set_angle_error_rad(required.angle_error_rad);
    out->set_position_ok(required.position_ok);
    out->set_angle_ok(required.angle_ok);
    out->set_correct(required.correct);
  }
  wire->set_summary(score.summary);
}

}  // namespace culinarycut::server
