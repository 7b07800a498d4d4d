// Scoring a cut (paper, "Success Criteria" and supplement "Split Cut Evaluation"): each required
// cut must lie within +-1/10 of the object's length of its target and the cut plane must be
// aligned with the target plane; split cuts also report how many cuts were placed correctly.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "sim/task/cut_spec.h"
#include "sim/task/object_box.h"

namespace culinarycut::task {

// A cut as measured after the episode: a plane through the object, or only a position (from
// piece boundaries) when the plane's orientation is unknown. Its orientation is measured twice:
// from the cut surface the blade left, and from the knife's pose while its edge passed the food.
struct MeasuredCut {
  std::string object_name;                     // ObjectBox::name of the object it went through
  Eigen::Vector3d plane_point_m = Eigen::Vector3d::Zero();  // a point on the cut plane (world)
  std::optional<Eigen::Vector3d> plane_normal;  // the cut surface's normal (world), if measured
  std::optional<Eigen::Vector3d> blade_normal;  // the blade's mean face normal in the food (world)
};

struct SuccessTolerances {
  // Paper: within one tenth of the object's total length, inclusive.
  double position_fraction = 0.1;
  // Paper: the blade-plane angle "within the same tolerance range"; we read that as one tenth
  // of the 90 deg range a plane's angle can take: 9 deg, inclusive.
  double angle_rad = 0.15707963267948966;
  // Bias cuts: the tilt from vertical (about the blade edge) that counts as a bias cut, the
  // planner's default sampling range (20-35 deg).
  double bias_min_rad = 0.35;
  double bias_max_rad = 0.61;
  // A cut on the target that matches no required cut fails the episode (an extra slice).
  bool allow_extra_cuts = false;
};

// Throws TaskError for negative tolerances or an inverted bias range.
void ValidateTolerances(const SuccessTolerances& tolerances);

// One required cut and how the measured cuts did against it.
struct RequiredCutScore {
  double target_fraction = 0.0;        // from the left end
  bool placed = false;                 // a measured cut was matched to it
  double measured_fraction = 0.0;      // of the matched cut (where its plane meets the long axis)
  double position_error_fraction = 0.0;  // |measured - target| / 1 (fractions of the length)
  bool angle_measured = false;
  double angle_error_rad = 0.0;        // cut surface to the target plane (bias: to the accepted tilt range)
  bool blade_angle_measured = false;
  double blade_angle_error_rad = 0.0;  // the blade in the food to the target plane, likewise
  bool position_ok = false;
  bool angle_ok = false;               // both measured angles within tolerance (an unmeasured one passes)
  bool correct = false;                // placed, position_ok and angle_ok
};

struct TaskScore {
  bool success = false;
  int cuts_required = 0;
  int cuts_correct = 0;                // required cuts correct in position and angle
  int cuts_within_position_tolerance = 0;  // required cuts within +-1/10 (the paper's split table)
  int extra_cuts = 0;                  // cuts on the target that match no required cut
  int wrong_object_cuts = 0;           // cuts through other objects
  std::vector<RequiredCutScore> required;  // in target order, left to right
  std::string summary;                 // one line: why it succeeded or failed
};

// Scores `measured` (cuts through any object of the scene) against `spec` on `target`, whose
// food must be spec.target_object. A cut through any other object fails the episode.
TaskScore ScoreCuts(const ObjectBox& target, const CutSpec& spec,
                    const std::vector<MeasuredCut>& measured,
                    const SuccessTolerances& tolerances = {});

// Where a measured cut lies along the target's long axis, as a fraction from the left end: the
// plane's intersection with the axis, or the point's projection when there is no normal.
// Returns nullopt for a plane parallel to the axis (it never crosses it).
std::optional<double> CutFractionAlongAxis(const LongAxis& axis, const MeasuredCut& cut);

// Position-only cuts from the world-space boxes (min, max corners) of the pieces an object broke
// into: one cut midway between each pair of neighbouring pieces along the long axis.
std::vector<MeasuredCut> CutsFromPieceBounds(
    const ObjectBox& object,
    const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& piece_bounds_m);

// The paper's partial-success table for split cuts: for each (food, pieces), how many episodes
// placed exactly k of the required cuts within the position tolerance (the paper counts position
// only; TaskScore::cuts_correct also checks the angle).
class PartialSuccessTable {
 public:
  void Add(const CutSpec& spec, const TaskScore& score);  // ignores non-split specs; validates spec
  // counts[k] = episodes with exactly k cuts within tolerance, k = 0 .. pieces - 1.
  const std::vector<int>& Counts(const std::string& food, int pieces) const;
  // Markdown table in percent of episodes, rows food x "1/n", columns k = 1 .. 4.
  std::string ToMarkdown() const;

 private:
  std::map<std::pair<std::string, int>, std::vector<int>> counts_;
};

}  // namespace culinarycut::task
