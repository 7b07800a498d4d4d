#include "sim/task/cut_spec.h"

#include <catch2/catch.hpp>

namespace culinarycut::task {
namespace {

CutSpec Cucumber(CutState state) {
  CutSpec spec;
  spec.state = state;
  spec.target_object = "cucumber";
  return spec;
}

TEST_CASE("paper's default rules fill a missing style or state", "[task][cut_spec]") {
  PartialCutSpec state_only;
  state_only.state = CutState::kRatio;
  state_only.ratio = 0.3;
  state_only.target_object = "banana";
  CHECK(ResolveDefaults(state_only).style == CutStyle::kNormal);

  PartialCutSpec style_only;
  style_only.style = CutStyle::kSaw;
  style_only.target_object = "banana";
  const CutSpec resolved = ResolveDefaults(style_only);
  CHECK(resolved.style == CutStyle::kSaw);
  CHECK(resolved.state == CutState::kMiddle);
}

TEST_CASE("target fractions for middle, ratio from both sides and splits", "[task][cut_spec]") {
  CHECK(TargetFractionsFromLeft(Cucumber(CutState::kMiddle)) == std::vector<double>{0.5});

  CutSpec ratio = Cucumber(CutState::kRatio);
  ratio.ratio = 0.3;
  ratio.reference = DirectionalReference::kLeft;
  CHECK(TargetFractionsFromLeft(ratio)[0] == Approx(0.3));
  ratio.reference = DirectionalReference::kRight;
  CHECK(TargetFractionsFromLeft(ratio)[0] == Approx(0.7));
  ratio.reference = DirectionalReference::kAlongLength;  // no side named: from the left
  CHECK(TargetFractionsFromLeft(ratio)[0] == Approx(0.3));

  CutSpec split = Cucumber(CutState::kSplit);
  split.split_pieces = 4;
  const auto fractions = TargetFractionsFromLeft(split);
  REQUIRE(fractions.size() == 3);
  CHECK(fractions[0] == Approx(0.25));
  CHECK(fractions[1] == Approx(0.5));
  CHECK(fractions[2] == Approx(0.75));
}

TEST_CASE("invalid specs are refused with the field named", "[task][cut_spec]") {
  CutSpec spec = Cucumber(CutState::kRatio);
  spec.ratio = 0.95;
  CHECK_THROWS_WITH(ValidateCutSpec(spec), Catch::Contains("ratio 0.95 is outside [0.1, 0.9]"));
  spec = Cucumber(CutState::kSplit);
  spec.split_pieces = 2;
  CHECK_THROWS_WITH(ValidateCutSpec(spec), Catch::Contains("3, 4 or 5"));
  spec = Cucumber(CutState::kMiddle);
  spec.target_object = "pineapple";
  CHECK_THROWS_WITH(ValidateCutSpec(spec), Catch::Contains("unknown target object 'pineapple'"));
  CHECK_THROWS_WITH(CutStyleFromName("chop"), Catch::Contains("normal, bias, guillotine, saw"));
}

TEST_CASE("equality ignores fields the state does not use", "[task][cut_spec]") {
  CutSpec a = Cucumber(CutState::kMiddle);
  CutSpec b = a;
  b.ratio = 0.2;
  b.split_pieces = 5;
  CHECK(a == b);
  a.state = b.state = CutState::kRatio;
  CHECK(a != b);
}

}  // namespace
}  // namespace culinarycut::task
