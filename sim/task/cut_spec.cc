#include "sim/task/cut_spec.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace culinarycut::task {
namespace {

constexpr double kRatioEqualityTolerance = 1e-9;

template <typename Enum>
struct NamedValue {
  Enum value;
  const char* name;
};

constexpr NamedValue<CutStyle> kStyleNames[] = {{CutStyle::kNormal, "normal"},
                                                {CutStyle::kBias, "bias"},
                                                {CutStyle::kGuillotine, "guillotine"},
                                                {CutStyle::kSaw, "saw"}};
constexpr NamedValue<CutState> kStateNames[] = {
    {CutState::kMiddle, "middle"}, {CutState::kRatio, "ratio"}, {CutState::kSplit, "split"}};
constexpr NamedValue<DirectionalReference> kReferenceNames[] = {
    {DirectionalReference::kNone, "none"},
    {DirectionalReference::kLeft, "left"},
    {DirectionalReference::kRight, "right"},
    {DirectionalReference::kTop, "top"},
    {DirectionalReference::kAlongLength, "along_length"}};

template <typename Enum, size_t N>
std::string NameOf(const NamedValue<Enum> (&table)[N], Enum value) {
  for (const auto& entry : table) {
    if (entry.value == value) return entry.name;
  }
  return "unknown";
}

template <typename Enum, size_t N>
Enum ValueOf(const NamedValue<Enum> (&table)[N], const std::string& name, const char* what) {
  std::string accepted;
  for (const auto& entry : table) {
    if (name == entry.name) return entry.value;
    accepted += accepted.empty() ? "" : ", ";
    accepted += entry.name;
  }
  throw TaskError("unknown " + std::string(what) + " '" + name + "'; expected one of: " + accepted);
}

}  // namespace

const std::vector<std::string>& KnownFoods() {
  static const std::vector<std::string> foods = {"orange", "strawberry", "melon", "cucumber",
                                                 "banana", "apple",      "peach"};
  return foods;
}

bool operator==(const CutSpec& a, const CutSpec& b) {
  if (a.style != b.style || a.state != b.state || a.target_object != b.target_object ||
      a.reference != b.reference) {
    return false;
  }
  if (a.state == CutState::kRatio) return std::abs(a.ratio - b.ratio) <= kRatioEqualityTolerance;
  if (a.state == CutState::kSplit) return a.split_pieces == b.split_pieces;
  return true;
}

CutSpec ResolveDefaults(const PartialCutSpec& partial) {
  CutSpec spec;
  spec.style = partial.style.value_or(CutStyle::kNormal);
  spec.state = partial.state.value_or(CutState::kMiddle);
  spec.ratio = partial.ratio;
  spec.split_pieces = partial.split_pieces;
  spec.target_object = partial.target_object;
  spec.reference = partial.reference;
  ValidateCutSpec(spec);
  return spec;
}

void ValidateCutSpec(const CutSpec& spec) {
  const auto& foods = KnownFoods();
  if (std::find(foods.begin(), foods.end(), spec.target_object) == foods.end()) {
    std::string accepted;
    for (const auto& food : foods) accepted += (accepted.empty() ? "" : ", ") + food;
    throw TaskError("unknown target object '" + spec.target_object + "'; expected one of: " +
                    accepted);
  }
  if (spec.state == CutState::kRatio &&
      !(spec.ratio >= kMinRatio - kRatioEqualityTolerance &&
        spec.ratio <= kMaxRatio + kRatioEqualityTolerance)) {
    std::ostringstream message;
    message << "ratio " << spec.ratio << " is outside [" << kMinRatio << ", " << kMaxRatio
            << "]; a ratio cut measures from one end of the object";
    throw TaskError(message.str());
  }
  if (spec.state == CutState::kSplit &&
      (spec.split_pieces < kMinSplitPieces || spec.split_pieces > kMaxSplitPieces)) {
    throw TaskError("split into " + std::to_string(spec.split_pieces) +
                    " pieces is not a task; split cuts make 3, 4 or 5 equal pieces");
  }
}

std::vector<double> TargetFractionsFromLeft(const CutSpec& spec) {
  switch (spec.state) {
    case CutState::kMiddle:
      return {0.5};
    case CutState::kRatio:
      return {spec.reference == DirectionalReference::kRight ? 1.0 - spec.ratio : spec.ratio};
    case CutState::kSplit: {
      std::vector<double> fractions;
      for (int cut = 1; cut < spec.split_pieces; ++cut) {
        fractions.push_back(static_cast<double>(cut) / spec.split_pieces);
      }
      return fractions;
    }
  }
  return {};
}

std::string Name(CutStyle style) { return NameOf(kStyleNames, style); }
std::string Name(CutState state) { return NameOf(kStateNames, state); }
std::string Name(DirectionalReference reference) { return NameOf(kReferenceNames, reference); }

CutStyle CutStyleFromName(const std::string& name) {
  return ValueOf(kStyleNames, name, "cut style");
}
CutState CutStateFromName(const std::string& name) {
  return ValueOf(kStateNames, name, "cut state");
}
DirectionalReference DirectionalReferenceFromName(const std::string& name) {
  return ValueOf(kReferenceNames, name, "directional reference");
}

std::string Describe(const CutSpec& spec) {
  std::ostringstream text;
  text << Name(spec.style) << " cut, ";
  switch (spec.state) {
    case CutState::kMiddle:
      text << "middle";
      break;
    case CutState::kRatio:
      text << "ratio " << spec.ratio << " from the "
           << (spec.reference == DirectionalReference::kRight ? "right" : "left");
      break;
    case CutState::kSplit:
      text << "split into " << spec.split_pieces << " pieces";
      break;
  }
  text << ", " << (spec.target_object.empty() ? "(no object)" : spec.target_object);
  return text.str();
}

}  // namespace culinarycut::task
