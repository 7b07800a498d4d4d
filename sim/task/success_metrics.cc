#include "sim/task/success_metrics.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace culinarycut::task {
namespace {

// Tolerance comparisons are inclusive; this absorbs rounding in a cut placed exactly at the edge.
constexpr double kToleranceSlack = 1e-9;
// A plane whose normal is this close to perpendicular to the axis never meets it usefully.
constexpr double kParallelPlaneCosine = 1e-6;

// Angle (rad) between the cut plane and the vertical plane normal to the long axis.
double AngleToPerpendicularPlane(const Eigen::Vector3d& axis, const Eigen::Vector3d& normal) {
  return std::acos(std::min(1.0, std::abs(axis.dot(normal.normalized()))));
}

// Angle (rad) from the plane to the nearest plane tilted about the blade edge (horizontal, normal
// to the axis) by an angle in [min_tilt, max_tilt] either way: twist and tilt miss combined.
double AngleToBiasPlanes(const Eigen::Vector3d& axis, const Eigen::Vector3d& normal,
                         double min_tilt_rad, double max_tilt_rad) {
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d edge = axis.cross(up).normalized();
  Eigen::Vector3d n = normal.normalized();
  if (n.dot(axis) < 0.0) n = -n;
  const double twist_rad = std::asin(std::min(1.0, std::abs(n.dot(edge))));
  const double tilt_rad = std::atan2(std::abs(n.dot(up)), n.dot(axis));
  const double tilt_miss_rad =
      std::max({0.0, min_tilt_rad - tilt_rad, tilt_rad - max_tilt_rad});
  return std::hypot(twist_rad, tilt_miss_rad);
}

// Angle (rad) from a measured plane normal to the task's target orientation.
double AngleErrorToTarget(CutStyle style, const Eigen::Vector3d& axis, const Eigen::Vector3d& normal,
                          const SuccessTolerances& tolerances) {
  return style == CutStyle::kBias
             ? AngleToBiasPlanes(axis, normal, tolerances.bias_min_rad, tolerances.bias_max_rad)
             : AngleToPerpendicularPlane(axis, normal);
}

std::string Percent(double fraction) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(1) << 100.0 * fraction << "%";
  return text.str();
}

}  // namespace

void ValidateTolerances(const SuccessTolerances& tolerances) {
  if (!(tolerances.position_fraction >= 0.0) || !(tolerances.angle_rad >= 0.0)) {
    throw TaskError("success tolerances must be >= 0 (position_fraction, angle_rad)");
  }
  if (!(tolerances.bias_min_rad >= 0.0 && tolerances.bias_min_rad <= tolerances.bias_max_rad &&
        tolerances.bias_max_rad < M_PI / 2)) {
    throw TaskError("bias tilt range must satisfy 0 <= bias_min_rad <= bias_max_rad < pi/2");
  }
}

std::optional<double> CutFractionAlongAxis(const LongAxis& axis, const MeasuredCut& cut) {
  const Eigen::Vector3d offset = cut.plane_point_m - axis.left_end_m;
  if (!cut.plane_normal) return offset.dot(axis.direction) / axis.length_m;
  const Eigen::Vector3d normal = cut.plane_normal->normalized();
  const double along = axis.direction.dot(normal);
  if (std::abs(along) < kParallelPlaneCosine) return std::nullopt;
  // Line left_end + s * direction meets the plane where (left_end + s*d - p) . n = 0.
  return offset.dot(normal) / along / axis.length_m;
}

TaskScore ScoreCuts(const ObjectBox& target, const CutSpec& spec,
                    const std::vector<MeasuredCut>& measured,
                    const SuccessTolerances& tolerances) {
  ValidateCutSpec(spec);
  ValidateObjectBox(target);
  ValidateTolerances(tolerances);
  if (target.food != spec.target_object) {
    throw TaskError("target object '" + target.name + "' is a " + target.food +
                    " but the task asks to cut the " + spec.target_object);
  }
  const LongAxis axis = LongAxisOf(target);
  TaskScore score;
  for (double fraction : TargetFractionsFromLeft(spec)) {
    RequiredCutScore required;
    required.target_fraction = fraction;
    score.required.push_back(required);
  }
  score.cuts_required = static_cast<int>(score.required.size());

  // Positions of the cuts through the target; cuts elsewhere fail the task outright.
  std::vector<std::optional<double>> fractions;
  std::vector<const MeasuredCut*> on_target;
  for (const MeasuredCut& cut : measured) {
    if (cut.object_name != target.name) {
      ++score.wrong_object_cuts;
      continue;
    }
    on_target.push_back(&cut);
    fractions.push_back(CutFractionAlongAxis(axis, cut));
  }

  // Match measured cuts to required cuts one to one. First as many within the position tolerance
  // as possible: targets and cuts in order along the axis, each target taking the first free cut
  // in its window (windows are equally wide, so this greedy count is the largest possible).
  std::vector<size_t> order(on_target.size());
  for (size_t c = 0; c < order.size(); ++c) order[c] = c;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return fractions[a].value_or(std::numeric_limits<double>::infinity()) <
           fractions[b].value_or(std::numeric_limits<double>::infinity());
  });
  std::vector<bool> cut_used(on_target.size(), false);
  std::vector<std::optional<size_t>> match(score.required.size());
  size_t next = 0;
  for (size_t r = 0; r < score.required.size(); ++r) {
    const double target = score.required[r].target_fraction;
    const double window = tolerances.position_fraction + kToleranceSlack;
    while (next < order.size() && fractions[order[next]] && *fractions[order[next]] < target - window) {
      ++next;
    }
    if (next < order.size() && fractions[order[next]] && *fractions[order[next]] <= target + window) {
      match[r] = order[next];
      cut_used[order[next]] = true;
      ++next;
    }
  }
  // Then the remaining targets take the closest remaining cuts, so misses report their error.
  struct Pair {
    double distance;
    size_t required;
    size_t cut;
  };
  std::vector<Pair> pairs;
  for (size_t r = 0; r < score.required.size(); ++r) {
    if (match[r]) continue;
    for (size_t c = 0; c < on_target.size(); ++c) {
      if (cut_used[c] || !fractions[c]) continue;
      pairs.push_back({std::abs(*fractions[c] - score.required[r].target_fraction), r, c});
    }
  }
  std::stable_sort(pairs.begin(), pairs.end(),
                   [](const Pair& a, const Pair& b) { return a.distance < b.distance; });
  for (const Pair& pair : pairs) {
    if (match[pair.required] || cut_used[pair.cut]) continue;
    match[pair.required] = pair.cut;
    cut_used[pair.cut] = true;
  }

  for (size_t r = 0; r < score.required.size(); ++r) {
    if (!match[r]) continue;
    RequiredCutScore& required = score.required[r];
    const MeasuredCut& cut = *on_target[*match[r]];
    required.placed = true;
    required.measured_fraction = *fractions[*match[r]];
    required.position_error_fraction = std::abs(required.measured_fraction - required.target_fraction);
    required.position_ok =
        required.position_error_fraction <= tolerances.position_fraction + kToleranceSlack;
    required.angle_measured = cut.plane_normal.has_value();
    if (required.angle_measured) {
      required.angle_error_rad = AngleErrorToTarget(spec.style, axis.direction, *cut.plane_normal, tolerances);
    }
    required.blade_angle_measured = cut.blade_normal.has_value();
    if (required.blade_angle_measured) {
      required.blade_angle_error_rad = AngleErrorToTarget(spec.style, axis.direction, *cut.blade_normal, tolerances);
    }
    const double angle_limit_rad = tolerances.angle_rad + kToleranceSlack;
    required.angle_ok = (!required.angle_measured || required.angle_error_rad <= angle_limit_rad) &&
                        (!required.blade_angle_measured || required.blade_angle_error_rad <= angle_limit_rad);
    required.correct = required.position_ok && required.angle_ok;
  }
  score.extra_cuts = static_cast<int>(std::count(cut_used.begin(), cut_used.end(), false));
  for (const RequiredCutScore& required : score.required) {
    score.cuts_correct += required.correct;
    score.cuts_within_position_tolerance += required.position_ok;
  }

  // The first reason that fails the task, in the order a person would check.
  std::ostringstream summary;
  if (score.wrong_object_cuts > 0) {
    summary << "failed: " << score.wrong_object_cuts << " cut(s) went through an object other than "
            << target.name;
  } else if (score.cuts_correct < score.cuts_required) {
    summary << "failed: " << score.cuts_correct << " of " << score.cuts_required
            << " required cut(s) placed correctly";
    for (const RequiredCutScore& required : score.required) {
      if (required.correct) continue;
      summary << "; target " << Percent(required.target_fraction) << ": ";
      if (!required.placed) {
        summary << "no cut";
      } else if (!required.position_ok) {
        summary << "cut at " << Percent(required.measured_fraction) << ", off by "
                << Percent(required.position_error_fraction) << " of the length";
      } else {
        summary << std::fixed << std::setprecision(1);
        if (required.angle_measured) summary << "cut surface off by " << required.angle_error_rad * 180.0 / M_PI << " deg";
        if (required.angle_measured && required.blade_angle_measured) summary << ", ";
        if (required.blade_angle_measured) {
          summary << "blade off by " << required.blade_angle_error_rad * 180.0 / M_PI << " deg";
        }
      }
    }
  } else if (score.extra_cuts > 0 && !tolerances.allow_extra_cuts) {
    summary << "failed: " << score.extra_cuts << " extra cut(s) on " << target.name;
  } else {
    score.success = true;
    summary << "success: " << score.cuts_correct << " of " << score.cuts_required
            << " cut(s) within " << Percent(tolerances.position_fraction) << " of the length";
  }
  score.summary = summary.str();
  return score;
}

std::vector<MeasuredCut> CutsFromPieceBounds(
    const ObjectBox& object,
    const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& piece_bounds_m) {
  const LongAxis axis = LongAxisOf(object);
  // Each piece's extent along the axis, from the projections of its box's corners.
  std::vector<std::pair<double, double>> intervals;
  for (const auto& [low, high] : piece_bounds_m) {
    double lowest = std::numeric_limits<double>::infinity();
    double highest = -lowest;
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d point((corner & 1) ? high.x() : low.x(), (corner & 2) ? high.y() : low.y(),
                                  (corner & 4) ? high.z() : low.z());
      const double along = (point - axis.left_end_m).dot(axis.direction);
      lowest = std::min(lowest, along);
      highest = std::max(highest, along);
    }
    intervals.emplace_back(lowest, highest);
  }
  std::sort(intervals.begin(), intervals.end(), [](const auto& a, const auto& b) {
    return a.first + a.second < b.first + b.second;
  });
  std::vector<MeasuredCut> cuts;
  for (size_t i = 1; i < intervals.size(); ++i) {
    const double boundary_m = 0.5 * (intervals[i - 1].second + intervals[i].first);
    MeasuredCut cut;
    cut.object_name = object.name;
    cut.plane_point_m = axis.left_end_m + boundary_m * axis.direction;
    cuts.push_back(cut);
  }
  return cuts;
}

void PartialSuccessTable::Add(const CutSpec& spec, const TaskScore& score) {
  if (spec.state != CutState::kSplit) return;
  ValidateCutSpec(spec);
  auto& counts = counts_[{spec.target_object, spec.split_pieces}];
  counts.resize(spec.split_pieces, 0);
  counts[std::clamp(score.cuts_within_position_tolerance, 0, spec.split_pieces - 1)] += 1;
}

const std::vector<int>& PartialSuccessTable::Counts(const std::string& food, int pieces) const {
  static const std::vector<int> kNone;
  const auto found = counts_.find({food, pieces});
  return found == counts_.end() ? kNone : found->second;
}

std::string PartialSuccessTable::ToMarkdown() const {
  std::ostringstream table;
  table << "| object | split | episodes | 1 | 2 | 3 | 4 |\n|---|---|---|---|---|---|---|\n";
  for (const auto& [key, counts] : counts_) {
    int episodes = 0;
    for (int count : counts) episodes += count;
    table << "| " << key.first << " | 1/" << key.second << " | " << episodes;
    for (int k = 1; k <= kMaxSplitPieces - 1; ++k) {
      table << " | ";
      if (k < static_cast<int>(counts.size())) {
        table << Percent(episodes ? static_cast<double>(counts[k]) / episodes : 0.0);
      } else {
        table << "--";
      }
    }
    table << " |\n";
  }
  return table.str();
}

}  // namespace culinarycut::task
