// What to cut and how: a cut style, a cut state, the target object and the directional reference
// (paper, "Task Definition" and supplement "Language Instruction Design").
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace culinarycut::task {

// Bad task input: an invalid cut spec, an instruction that cannot be parsed, an impossible plan.
class TaskError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// How the knife moves through the food.
enum class CutStyle { kNormal, kBias, kGuillotine, kSaw };
// Where the cut (or cuts) go along the object's long axis.
enum class CutState { kMiddle, kRatio, kSplit };
// Which phrase anchors the position. Only kLeft and kRight change where a ratio cut goes;
// the others are kept so that an instruction and its spec round-trip exactly.
enum class DirectionalReference { kNone, kLeft, kRight, kTop, kAlongLength };

// The foods of the paper, in its order.
const std::vector<std::string>& KnownFoods();

inline constexpr double kMinRatio = 0.1;  // paper: ratio cuts from 0.1 to 0.9
inline constexpr double kMaxRatio = 0.9;
inline constexpr int kMinSplitPieces = 3;  // paper: 3-, 4- and 5-way splits
inline constexpr int kMaxSplitPieces = 5;

struct CutSpec {
  CutStyle style = CutStyle::kNormal;
  CutState state = CutState::kMiddle;
  // kRatio only: fraction of the object's length, measured from the end `reference` names
  // (kLeft or kRight); any other reference measures from the left end.
  double ratio = 0.5;
  // kSplit only: number of equal pieces (3, 4 or 5), so pieces - 1 cuts.
  int split_pieces = 3;
  std::string target_object;  // a food name from KnownFoods()
  DirectionalReference reference = DirectionalReference::kNone;
};

// Equal when every field that matters for the spec's state is equal (ratio within 1e-9).
bool operator==(const CutSpec& a, const CutSpec& b);
inline bool operator!=(const CutSpec& a, const CutSpec& b) { return !(a == b); }

// What an instruction said before the paper's default rules fill the gaps.
struct PartialCutSpec {
  std::optional<CutStyle> style;
  std::optional<CutState> state;
  double ratio = 0.5;
  int split_pieces = 3;
  std::string target_object;
  DirectionalReference reference = DirectionalReference::kNone;
};

// The paper's default rules: a state only -> Normal style; a style only -> Middle state;
// neither -> Normal + Middle. Validates the result.
CutSpec ResolveDefaults(const PartialCutSpec& partial);

// Throws TaskError naming the bad field: unknown food, ratio outside [0.1, 0.9], pieces outside 3..5.
void ValidateCutSpec(const CutSpec& spec);

// Cut positions as fractions of the length from the LEFT end, ascending: middle -> {0.5};
// ratio r from the left -> {r}, from the right -> {1 - r}; split n -> {1/n, ..., (n-1)/n}.
std::vector<double> TargetFractionsFromLeft(const CutSpec& spec);

// Names used on the wire, in files and in messages: "normal", "bias", "guillotine", "saw";
// "middle", "ratio", "split"; "none", "left", "right", "top", "along_length".
std::string Name(CutStyle style);
std::string Name(CutState state);
std::string Name(DirectionalReference reference);
// Inverse of Name(); throws TaskError listing the accepted names.
CutStyle CutStyleFromName(const std::string& name);
CutState CutStateFromName(const std::string& name);
DirectionalReference DirectionalReferenceFromName(const std::string& name);

// One line for logs and errors, e.g. "saw cut, ratio 0.3 from the left, cucumber".
std::string Describe(const CutSpec& spec);

}  // namespace culinarycut::task
