#include "sim/task/instruction_parser.h"

#include <chrono>
#include <vector>

#include <catch2/catch.hpp>

#include "sim/task/instruction_generator.h"

namespace culinarycut::task {
namespace {

CutSpec Spec(CutStyle style, CutState state, const std::string& food,
             DirectionalReference reference = DirectionalReference::kNone, double ratio = 0.5,
             int pieces = 3) {
  CutSpec spec;
  spec.style = style;
  spec.state = state;
  spec.target_object = food;
  spec.reference = reference;
  spec.ratio = ratio;
  spec.split_pieces = pieces;
  return spec;
}

struct RoundTrip {
  size_t total = 0;
  size_t exact = 0;
  std::string first_failure;
};

TEST_CASE("generation then parsing round-trips over the whole template space",
          "[task][language][round_trip]") {
  RoundTrip train;
  RoundTrip held_out;
  const auto start = std::chrono::steady_clock::now();
  const auto specs = EnumerateTaskSpecs();
  for (const CutSpec& spec : specs) {
    for (const auto& instruction : EnumerateLabelledInstructions(spec)) {
      RoundTrip& tally = instruction.split == LanguageSplit::kTrain ? train : held_out;
      ++tally.total;
      std::string failure;
      try {
        const CutSpec parsed = ParseInstruction(instruction.text);
        if (parsed == spec) {
          ++tally.exact;
        } else {
          failure = "parsed as " + Describe(parsed) + " / " + Name(parsed.reference);
        }
      } catch (const TaskError& error) {
        failure = error.what();
      }
      if (!failure.empty() && tally.first_failure.empty()) {
        tally.first_failure = "\"" + instruction.text + "\" (want " + Describe(spec) + " / " +
                              Name(spec.reference) + "): " + failure;
      }
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto rate = [](const RoundTrip& tally) {
    return static_cast<double>(tally.exact) / static_cast<double>(tally.total);
  };
  WARN("round trip over " << specs.size() << " task specs in " << seconds << " s: train "
                          << train.exact << "/" << train.total << " exact (" << 100 * rate(train)
                          << "%), held-out " << held_out.exact << "/" << held_out.total
                          << " exact (" << 100 * rate(held_out) << "%)");
  INFO("first train failure: " << train.first_failure);
  INFO("first held-out failure: " << held_out.first_failure);
  REQUIRE(train.total > 0);
  REQUIRE(held_out.total > 0);
  CHECK(rate(train) >= 0.995);
  CHECK(rate(held_out) >= 0.995);
  // The data and the parser are built together: every generated instruction parses exactly.
  CHECK(train.exact == train.total);
  CHECK(held_out.exact == held_out.total);
}

TEST_CASE("the paper's sample instructions parse to their specs", "[task][language]") {
  using R = DirectionalReference;
  CHECK(ParseInstruction("Normal Cut the banana at 0.3 ratio from the right side.") ==
        Spec(CutStyle::kNormal, CutState::kRatio, "banana", R::kRight, 0.3));
  CHECK(ParseInstruction("Normal Cut the apple at the midpoint along its length.") ==
        Spec(CutStyle::kNormal, CutState::kMiddle, "apple", R::kAlongLength));
  // "toward the right end" counts from the left end, moving right: 0.4 from the left.
  CHECK(ParseInstruction("Bias cut the apple at 0.4 ratio toward the right end.") ==
        Spec(CutStyle::kBias, CutState::kRatio, "apple", R::kLeft, 0.4));
  CHECK(TargetFractionsFromLeft(
            ParseInstruction("Bias cut the apple at 0.4 ratio toward the right end.")) ==
        std::vector<double>{0.4});
  CHECK(ParseInstruction("Bias cut the melon at the midpoint from the left side.") ==
        Spec(CutStyle::kBias, CutState::kMiddle, "melon", R::kLeft));
  CHECK(ParseInstruction("Guillotine cut the orange at 0.5 ratio from the left side.") ==
        Spec(CutStyle::kGuillotine, CutState::kRatio, "orange", R::kLeft, 0.5));
  CHECK(ParseInstruction("Guillotine cut the peach at the center from the top direction.") ==
        Spec(CutStyle::kGuillotine, CutState::kMiddle, "peach", R::kTop));
  CHECK(ParseInstruction("Saw cut the cucumber at 0.6 ratio along its length.") ==
        Spec(CutStyle::kSaw, CutState::kRatio, "cucumber", R::kAlongLength, 0.6));
  CHECK(ParseInstruction("Saw cut the strawberry at the midpoint from the right side.") ==
        Spec(CutStyle::kSaw, CutState::kMiddle, "strawberry", R::kRight));
  CHECK(ParseInstruction("cut the banana at 0.5 ratio from the right side") ==
        Spec(CutStyle::kNormal, CutState::kRatio, "banana", R::kRight, 0.5));
  CHECK(ParseInstruction("slice the banana halfway along its length") ==
        Spec(CutStyle::kNormal, CutState::kRatio, "banana", R::kAlongLength, 0.5));
  CHECK(ParseInstruction("cut at one-third from the left of the cucumber") ==
        Spec(CutStyle::kNormal, CutState::kRatio, "cucumber", R::kLeft, 1.0 / 3.0));
}

TEST_CASE("free text outside the templates parses where it is clear", "[task][language]") {
  using R = DirectionalReference;
  CHECK(ParseInstruction("cut the cucumber at 0.3 ratio from the left") ==
        Spec(CutStyle::kNormal, CutState::kRatio, "cucumber", R::kLeft, 0.3));
  CHECK(ParseInstruction("please slice the apple in half") ==
        Spec(CutStyle::kNormal, CutState::kRatio, "apple", R::kNone, 0.5));
  CHECK(ParseInstruction("saw the banana into 4 pieces") ==
        Spec(CutStyle::kSaw, CutState::kSplit, "banana", R::kNone, 0.5, 4));
  CHECK(ParseInstruction("cut 30% from the right of the melon") ==
        Spec(CutStyle::kNormal, CutState::kRatio, "melon", R::kRight, 0.3));
  CHECK(ParseInstruction("Slice the bananas into five equal-sized chunks!") ==
        Spec(CutStyle::kNormal, CutState::kSplit, "banana", R::kNone, 0.5, 5));
  CHECK(ParseInstruction("make two cuts in the cucumber") ==
        Spec(CutStyle::kNormal, CutState::kSplit, "cucumber", R::kNone, 0.5, 3));
  CHECK(ParseInstruction("bias cut the peach") ==
        Spec(CutStyle::kBias, CutState::kMiddle, "peach"));
  CHECK(ParseInstruction("cut the orange right in the middle") ==
        Spec(CutStyle::kNormal, CutState::kMiddle, "orange"));
  CHECK(ParseInstruction("diagonally cut the apple .25 of the way from its right end") ==
        Spec(CutStyle::kBias, CutState::kRatio, "apple", R::kRight, 0.25));
  CHECK(ParseInstruction("cut the melon in half at the centre") ==
        Spec(CutStyle::kNormal, CutState::kMiddle, "melon"));
  CHECK(ParseInstruction("cut the banana at twenty-five percent from the left") ==
        Spec(CutStyle::kNormal, CutState::kRatio, "banana", R::kLeft, 0.25));
  CHECK(ParseInstruction("chop the apple into a 3-way split").split_pieces == 3);
  CHECK(ParseInstruction("cut the cucumber at 0.3 ratio towards the left side") ==
        Spec(CutStyle::kNormal, CutState::kRatio, "cucumber", R::kRight, 0.3));
  CHECK(ParseInstruction("cut the cucumber 30% from the left, toward the right end") ==
        Spec(CutStyle::kNormal, CutState::kRatio, "cucumber", R::kLeft, 0.3));
  CHECK(ParseInstruction("cut one apple into 3 pieces") ==
        Spec(CutStyle::kNormal, CutState::kSplit, "apple", R::kNone, 0.5, 3));
  CHECK(ParseInstruction("saw the cucumber back and forth at two thirds").ratio ==
        Approx(2.0 / 3.0));
}

TEST_CASE("a ratio comes back exactly, never rounded", "[task][language]") {
  CHECK(ParseInstruction("cut the apple at one third").ratio == 1.0 / 3.0);
  CHECK(ParseInstruction("cut the apple at the 2/3 mark").ratio == 2.0 / 3.0);
  CHECK(ParseInstruction("cut the apple at 30 percent").ratio == 0.3);
}

TEST_CASE("text that cannot be parsed says what is missing or ambiguous", "[task][language]") {
  CHECK_THROWS_WITH(ParseInstruction("   "), Catch::Contains("it is empty"));
  CHECK_THROWS_WITH(ParseInstruction("cut it at 0.3 ratio from the left"),
                    Catch::Contains("names no food; expected one of: orange, strawberry, melon, "
                                    "cucumber, banana, apple, peach"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana and the apple in half"),
                    Catch::Contains("two foods, 'banana' and 'apple'"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana at 0.3 ratio, 40% from the left"),
                    Catch::Contains("two conflicting quantities, '0.3' (0.3) and '40 %' (0.4)"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana at 0.95 ratio"),
                    Catch::Contains("ratio 0.95 ('0.95') is outside [0.1, 0.9]"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana at 5%"),
                    Catch::Contains("ratio 0.05 ('5 %') is outside [0.1, 0.9]"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana into 2 pieces"),
                    Catch::Contains("asks for 2 pieces ('2 pieces'); a split makes 3, 4 or 5"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana into 7 pieces"),
                    Catch::Contains("asks for 7 pieces"));
  CHECK_THROWS_WITH(ParseInstruction("bias saw the banana"),
                    Catch::Contains("two cut styles, bias and saw"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana at 30% from the left and from the right"),
                    Catch::Contains("both the left and the right; say which end"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana at 30% from the right toward the right end"),
                    Catch::Contains("both the left and the right ('toward the right end' counts "
                                    "from the left"));
  CHECK_THROWS_WITH(ParseInstruction("split the banana evenly"),
                    Catch::Contains("a split but not into how many pieces"));
  CHECK_THROWS_WITH(ParseInstruction("Saw cut the banana at the third boundary toward the right"),
                    Catch::Contains("a split but not into how many pieces"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana at a ratio from the left"),
                    Catch::Contains("mentions a ratio but gives no value"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana at 0.3 ratio into 3 pieces"),
                    Catch::Contains("both a ratio ('0.3') and a piece count ('3 pieces')"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana at the middle, 30% from the left"),
                    Catch::Contains("both the middle and ratio 0.3"));
  CHECK_THROWS_WITH(ParseInstruction("cut the banana at 7 from the left"),
                    Catch::Contains("the number '7' is neither a ratio"));
  // A number word outside a quantity or piece count is as wrong as a stray digit: "three times"
  // must not quietly become a single Middle cut.
  CHECK_THROWS_WITH(ParseInstruction("cut the cucumber three times"),
                    Catch::Contains("the number 'three' is neither a ratio (e.g. 0.3 ratio, 30%) "
                                    "nor a piece count (e.g. into 3 pieces)"));
  CHECK_THROWS_WITH(ParseInstruction("cut the cucumber 3 times"),
                    Catch::Contains("the number '3' is neither a ratio"));
  CHECK_THROWS_WITH(ParseInstruction("cut the cucumber twenty five times"),
                    Catch::Contains("the number 'twenty five' is neither a ratio"));
  // Digit strings are bounded, never overflowed.
  CHECK_THROWS_WITH(ParseInstruction("cut the apple at 99999999999999999999/3"),
                    Catch::Contains("the number '99999999999999999999/3' is too large"));
  CHECK_THROWS_WITH(ParseInstruction("cut the apple at 3/99999999999999999999"),
                    Catch::Contains("the number '3/99999999999999999999' is too large"));
  CHECK_THROWS_WITH(ParseInstruction("cut the apple into 12345678901 pieces"),
                    Catch::Contains("the number '12345678901' is too large"));
  CHECK_THROWS_WITH(ParseInstruction("cut the apple at 1/0"),
                    Catch::Contains("the fraction '1/0' divides by zero"));
  CHECK_THROWS_WITH(ParseInstruction("cut the apple at 2000000/3000000"),
                    Catch::Contains("is too large"));
}

TEST_CASE("the partial parse leaves unnamed fields empty for the default rules",
          "[task][language]") {
  const PartialCutSpec partial = ParseInstructionPartial("saw through it at 40%");
  CHECK(partial.style == CutStyle::kSaw);
  CHECK(partial.state == CutState::kRatio);
  CHECK(partial.target_object.empty());
  CHECK_FALSE(ParseInstructionPartial("cut the apple").style.has_value());
  CHECK_FALSE(ParseInstructionPartial("cut the apple").state.has_value());
}

}  // namespace
}  // namespace culinarycut::task
