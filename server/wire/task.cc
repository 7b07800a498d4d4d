#include "server/wire/task.h"

#include <cmath>

#include "server/wire/values.h"

namespace culinarycut::server {
namespace {

void Vector3ToWire(const Eigen::Vector3d& vector, google::protobuf::RepeatedField<double>* wire) {
  AssignVector(vector, wire);
}

// Overrides `range` when the message is set; both ends must be finite.
void SampledRangeFromWire(bool present, const v1::Range& wire, const std::string& field, task::SampledRange* range) {
  if (present) *range = {FiniteFromWire(wire.min(), field + ".min"), FiniteFromWire(wire.max(), field + ".max")};
}

// Overrides `value` when the wrapper is set; it must be finite.
template <typename Wrapper>
void OptionalFromWire(bool present, const Wrapper& wire, const std::string& field, double* value) {
  if (present) *value = FiniteFromWire(wire.value(), field);
}

// A name the task module parses (style, state, reference), its error re-thrown naming the field.
template <typename Parse>
auto NameFromWire(const std::string& name, const std::string& field, Parse&& parse) {
  try {
    return parse(name);
  } catch (const task::TaskError& error) {
    throw FieldError(field, std::string("'") + name.substr(0, 64) + "': " + error.what());
  }
}

}  // namespace

task::CutSpec CutSpecFromWire(const v1::CutSpec& wire, const std::string& field) {
  task::CutSpec spec;
  if (!wire.style().empty()) spec.style = NameFromWire(wire.style(), field + ".style", task::CutStyleFromName);
  if (!wire.state().empty()) spec.state = NameFromWire(wire.state(), field + ".state", task::CutStateFromName);
  spec.ratio = FiniteFromWire(wire.ratio(), field + ".ratio");
  spec.split_pieces = CountFromWire(wire.split_pieces(), 1000, field + ".split_pieces");
  spec.target_object = wire.target_object();
  if (!wire.reference().empty()) {
    spec.reference = NameFromWire(wire.reference(), field + ".reference", task::DirectionalReferenceFromName);
  }
  if (spec.target_object.empty()) {
    throw FieldError(field + ".target_object", "is empty; name the food to cut, e.g. \"cucumber\"");
  }
  CheckField(field, [&] { task::ValidateCutSpec(spec); });
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

task::ObjectBox ObjectBoxFromWire(const v1::ObjectBox& wire, const std::string& field) {
  task::ObjectBox box;
  box.name = wire.name().empty() ? wire.food() : wire.name();
  box.food = wire.food();
  if (box.food.empty()) throw FieldError(field + ".food", "is empty; name its food type");
  if (!wire.has_pose()) throw FieldError(field + ".pose", "is missing");
  box.pose = PoseFromWire(wire.pose(), field + ".pose");
  box.extent_m = Vector3FromWire(wire.extent_m(), field + ".extent_m");
  CheckField(field, [&] { task::ValidateObjectBox(box); });
  return box;
}

task::PlannerOptions PlannerOptionsFromWire(const v1::PlannerOptions& wire, const std::string& field) {
  task::PlannerOptions options;
  OptionalFromWire(wire.has_approach_clearance_m(), wire.approach_clearance_m(), field + ".approach_clearance_m",
                   &options.approach_clearance_m);
  SampledRangeFromWire(wire.has_cut_start_height_m(), wire.cut_start_height_m(), field + ".cut_start_height_m",
                       &options.cut_start_height_m);
  SampledRangeFromWire(wire.has_cut_speed_m_s(), wire.cut_speed_m_s(), field + ".cut_speed_m_s", &options.cut_speed_m_s);
  SampledRangeFromWire(wire.has_saw_cut_speed_m_s(), wire.saw_cut_speed_m_s(), field + ".saw_cut_speed_m_s",
                       &options.saw_cut_speed_m_s);
  OptionalFromWire(wire.has_cut_end_below_bottom_m(), wire.cut_end_below_bottom_m(), field + ".cut_end_below_bottom_m",
                   &options.cut_end_below_bottom_m);
  OptionalFromWire(wire.has_max_linear_speed_m_s(), wire.max_linear_speed_m_s(), field + ".max_linear_speed_m_s",
                   &options.max_linear_speed_m_s);
  OptionalFromWire(wire.has_max_angular_speed_rad_s(), wire.max_angular_speed_rad_s(),
                   field + ".max_angular_speed_rad_s", &options.max_angular_speed_rad_s);
  SampledRangeFromWire(wire.has_bias_angle_rad(), wire.bias_angle_rad(), field + ".bias_angle_rad",
                       &options.bias_angle_rad);
  SampledRangeFromWire(wire.has_saw_frequency_hz(), wire.saw_frequency_hz(), field + ".saw_frequency_hz",
                       &options.saw_frequency_hz);
  SampledRangeFromWire(wire.has_saw_amplitude_m(), wire.saw_amplitude_m(), field + ".saw_amplitude_m",
                       &options.saw_amplitude_m);
  SampledRangeFromWire(wire.has_guillotine_start_pitch_rad(), wire.guillotine_start_pitch_rad(),
                       field + ".guillotine_start_pitch_rad", &options.guillotine_start_pitch_rad);
  CheckField(field, [&] { task::ValidatePlannerOptions(options); });
  return options;
}

task::SuccessTolerances TolerancesFromWire(const v1::SuccessTolerances& wire, const std::string& field) {
  task::SuccessTolerances tolerances;
  OptionalFromWire(wire.has_position_fraction(), wire.position_fraction(), field + ".position_fraction",
                   &tolerances.position_fraction);
  OptionalFromWire(wire.has_angle_rad(), wire.angle_rad(), field + ".angle_rad", &tolerances.angle_rad);
  if (wire.has_bias_rad()) {
    tolerances.bias_min_rad = FiniteFromWire(wire.bias_rad().min(), field + ".bias_rad.min");
    tolerances.bias_max_rad = FiniteFromWire(wire.bias_rad().max(), field + ".bias_rad.max");
  }
  tolerances.allow_extra_cuts = wire.allow_extra_cuts();
  CheckField(field, [&] { task::ValidateTolerances(tolerances); });
  return tolerances;
}

task::MeasuredCut MeasuredCutFromWire(const v1::MeasuredCut& wire, const std::string& field) {
  task::MeasuredCut cut;
  cut.object_name = wire.object_name();
  if (cut.object_name.empty()) throw FieldError(field + ".object_name", "is empty");
  cut.plane_point_m = Vector3FromWire(wire.plane_point_m(), field + ".plane_point_m");
  if (wire.plane_normal_size() > 0) {
    const Eigen::Vector3d normal = Vector3FromWire(wire.plane_normal(), field + ".plane_normal");
    if (normal.norm() == 0.0) throw FieldError(field + ".plane_normal", "has zero length");
    cut.plane_normal = normal.normalized();
  }
  if (wire.blade_normal_size() > 0) {
    const Eigen::Vector3d normal = Vector3FromWire(wire.blade_normal(), field + ".blade_normal");
    if (normal.norm() == 0.0) throw FieldError(field + ".blade_normal", "has zero length");
    cut.blade_normal = normal.normalized();
  }
  return cut;
}

void CutPlanToWire(const task::CutTrajectory& trajectory, const std::string& target_name,
                   double sample_rate_hz, v1::CutPlan* wire) {
  // Keeps a long plan at a high rate within gRPC's default 4 MB message limit (~130 B a sample).
  constexpr double kMaxSamples = 20000;
  if (trajectory.duration_s() * sample_rate_hz + 1 > kMaxSamples) {
    throw FieldError("sample_rate_hz", "gives more than " + std::to_string(static_cast<int>(kMaxSamples)) +
                                           " samples: the plan lasts " + std::to_string(trajectory.duration_s()) +
                                           " s at " + std::to_string(sample_rate_hz) + " Hz; lower sample_rate_hz");
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
    out->set_blade_angle_measured(required.blade_angle_measured);
    out->set_blade_angle_error_rad(required.blade_angle_error_rad);
    out->set_position_ok(required.position_ok);
    out->set_angle_ok(required.angle_ok);
    out->set_correct(required.correct);
  }
  wire->set_summary(score.summary);
}

}  // namespace culinarycut::server
