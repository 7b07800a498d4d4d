#include "sim/task/instruction_generator.h"

#include <algorithm>
#include <set>
#include <unordered_set>

#include <catch2/catch.hpp>

#include "sim/task/instruction_templates.h"

namespace culinarycut::task {
namespace {

CutSpec Spec(CutStyle style, CutState state, const std::string& food,
             DirectionalReference reference = DirectionalReference::kNone) {
  CutSpec spec;
  spec.style = style;
  spec.state = state;
  spec.target_object = food;
  spec.reference = reference;
  return spec;
}

bool Contains(const std::vector<std::string>& texts, const std::string& wanted) {
  const auto lower = [](std::string text) {
    for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
  };
  return std::any_of(texts.begin(), texts.end(),
                     [&](const std::string& text) { return lower(text) == lower(wanted); });
}

// Templates that describe `style` (a template without {verb} only describes Normal).
int TemplatesFor(CutStyle style, CutState state, PhraseSplit split) {
  int count = 0;
  for (const auto& instruction_template : DefaultInstructionTemplates().For(state)) {
    if (instruction_template.split != split) continue;
    if (style == CutStyle::kNormal || instruction_template.HasPlaceholder("verb")) ++count;
  }
  return count;
}

TEST_CASE("every style x state has at least 5 train and 2 held-out templates",
          "[task][language]") {
  for (CutStyle style :
       {CutStyle::kNormal, CutStyle::kBias, CutStyle::kGuillotine, CutStyle::kSaw}) {
    for (CutState state : {CutState::kMiddle, CutState::kRatio, CutState::kSplit}) {
      INFO(Name(style) << " x " << Name(state));
      CHECK(TemplatesFor(style, state, PhraseSplit::kTrain) >= 5);
      CHECK(TemplatesFor(style, state, PhraseSplit::kHeldOut) >= 2);
    }
  }
}

TEST_CASE("the paper's sample phrasings are generated", "[task][language]") {
  CutSpec ratio = Spec(CutStyle::kNormal, CutState::kRatio, "banana", DirectionalReference::kRight);
  ratio.ratio = 0.3;
  CHECK(Contains(EnumerateInstructions(ratio, LanguageSplit::kTrain),
                 "Normal Cut the banana at 0.3 ratio from the right side"));
  ratio.ratio = 0.5;
  CHECK(Contains(EnumerateInstructions(ratio, LanguageSplit::kTrain),
                 "cut the banana at 0.5 ratio from the right side"));

  // "toward the right end" counts from the left end, moving toward the right.
  CutSpec bias = Spec(CutStyle::kBias, CutState::kRatio, "apple", DirectionalReference::kLeft);
  bias.ratio = 0.4;
  CHECK(Contains(EnumerateInstructions(bias, LanguageSplit::kTrain),
                 "Bias cut the apple at 0.4 ratio toward the right end"));
  bias.reference = DirectionalReference::kRight;
  CHECK_FALSE(Contains(EnumerateInstructions(bias, LanguageSplit::kAll),
                       "Bias cut the apple at 0.4 ratio toward the right end"));
  CHECK(Contains(EnumerateInstructions(bias, LanguageSplit::kTrain),
                 "Bias cut the apple at 0.4 ratio toward the left end"));

  CutSpec saw =
      Spec(CutStyle::kSaw, CutState::kRatio, "cucumber", DirectionalReference::kAlongLength);
  saw.ratio = 0.6;
  CHECK(Contains(EnumerateInstructions(saw, LanguageSplit::kTrain),
                 "Saw cut the cucumber at 0.6 ratio along its length"));
  CutSpec halfway = Spec(CutStyle::kNormal, CutState::kRatio, "banana",
                         DirectionalReference::kAlongLength);
  halfway.ratio = 0.5;
  CHECK(Contains(EnumerateInstructions(halfway, LanguageSplit::kTrain),
                 "slice the banana halfway along its length"));

  CHECK(Contains(EnumerateInstructions(Spec(CutStyle::kGuillotine, CutState::kMiddle, "peach",
                                            DirectionalReference::kTop),
                                       LanguageSplit::kTrain),
                 "Guillotine cut the peach at the center from the top direction"));
  CHECK(Contains(EnumerateInstructions(Spec(CutStyle::kBias, CutState::kMiddle, "melon",
                                            DirectionalReference::kLeft),
                                       LanguageSplit::kTrain),
                 "Bias cut the melon at the midpoint from the left side"));
}

TEST_CASE("quantities are worded only with their exact value", "[task][language]") {
  CutSpec third = Spec(CutStyle::kNormal, CutState::kRatio, "cucumber",
                       DirectionalReference::kLeft);
  third.ratio = 1.0 / 3.0;
  const auto texts = EnumerateInstructions(third, LanguageSplit::kAll);
  CHECK(Contains(texts, "Cut the cucumber at one-third from the left"));
  CHECK(Contains(texts, "Cut the cucumber at the 1/3 mark from the left"));
  for (const auto& text : texts) {
    INFO(text);
    CHECK(text.find("0.3") == std::string::npos);
    CHECK(text.find('%') == std::string::npos);
  }
  CutSpec half = third;
  half.ratio = 0.5;
  const auto halves = EnumerateInstructions(half, LanguageSplit::kAll);
  CHECK(Contains(halves, "Cut the cucumber at two quarters from the left"));
  CHECK(Contains(halves, "Cut the cucumber at 50% from the left"));
  CHECK(Contains(halves, "Cut the cucumber at fifty percent from the left"));
}

TEST_CASE("split phrasings name the piece count", "[task][language]") {
  CutSpec split = Spec(CutStyle::kSaw, CutState::kSplit, "cucumber");
  split.split_pieces = 5;
  const auto texts = EnumerateInstructions(split, LanguageSplit::kAll);
  CHECK(Contains(texts, "Saw the cucumber into fifths"));
  CHECK(Contains(texts, "Saw cut the cucumber into 5 even slices"));
  CHECK(Contains(EnumerateInstructions(Spec(CutStyle::kNormal, CutState::kSplit, "banana"),
                                       LanguageSplit::kTrain),
                 "Split the banana into three parts"));
}

TEST_CASE("a style alone and a plain verb alone rely on the default rules", "[task][language]") {
  CHECK(Contains(
      EnumerateInstructions(Spec(CutStyle::kSaw, CutState::kMiddle, "banana"), LanguageSplit::kAll),
      "Saw cut the banana"));
  CHECK(Contains(EnumerateInstructions(Spec(CutStyle::kNormal, CutState::kMiddle, "banana"),
                                       LanguageSplit::kAll),
                 "Cut the banana"));
}

TEST_CASE("every task has at least 5 instructions in each split, and the splits are disjoint",
          "[task][language]") {
  const auto specs = EnumerateTaskSpecs();
  // 7 foods x 4 styles x (5 middle + 13 ratios x 4 references + 3 splits x 3 references).
  CHECK(specs.size() == 7 * 4 * (5 + 13 * 4 + 3 * 3));
  size_t train_total = 0;
  size_t held_out_total = 0;
  size_t duplicates_or_overlaps = 0;
  std::string first_problem;
  for (const CutSpec& spec : specs) {
    std::unordered_set<std::string> train;
    std::unordered_set<std::string> held_out;
    for (const auto& instruction : EnumerateLabelledInstructions(spec)) {
      const bool is_train = instruction.split == LanguageSplit::kTrain;
      const bool fresh = (is_train ? train : held_out).insert(instruction.text).second;
      // Train strings come first for no spec in particular, so check both directions.
      const bool overlaps = (is_train ? held_out : train).count(instruction.text) > 0;
      if (!fresh || overlaps) {
        ++duplicates_or_overlaps;
        if (first_problem.empty()) first_problem = instruction.text;
      }
    }
    INFO(Describe(spec) << " reference " << Name(spec.reference));
    REQUIRE(train.size() >= 5);
    REQUIRE(held_out.size() >= 5);
    train_total += train.size();
    held_out_total += held_out.size();
  }
  INFO("first duplicate or overlap: " << first_problem);
  CHECK(duplicates_or_overlaps == 0);
  WARN("task specs " << specs.size() << ", train instructions " << train_total
                     << ", held-out instructions " << held_out_total);
}

TEST_CASE("generation is deterministic for a seed and varies across seeds", "[task][language]") {
  CutSpec spec = Spec(CutStyle::kBias, CutState::kRatio, "apple", DirectionalReference::kRight);
  spec.ratio = 0.4;
  const auto first = GenerateInstructions(spec, 7, 5, LanguageSplit::kTrain);
  CHECK(first == GenerateInstructions(spec, 7, 5, LanguageSplit::kTrain));
  CHECK(first != GenerateInstructions(spec, 8, 5, LanguageSplit::kTrain));
  CHECK(std::set<std::string>(first.begin(), first.end()).size() == 5);
  const auto train = EnumerateInstructions(spec, LanguageSplit::kTrain);
  for (const auto& text : first) CHECK(Contains(train, text));
  for (const auto& text : GenerateInstructions(spec, 7, 5, LanguageSplit::kHeldOut)) {
    CHECK_FALSE(Contains(train, text));
  }
  CHECK_THROWS_WITH(GenerateInstructions(spec, 7, 1000000, LanguageSplit::kAll),
                    Catch::Contains("cannot draw 1000000 distinct instructions"));
}

TEST_CASE("a reference the state's templates never carry is named with the ones they do",
          "[task][language]") {
  CutSpec split = Spec(CutStyle::kNormal, CutState::kSplit, "cucumber",
                       DirectionalReference::kLeft);
  CHECK(EnumerateInstructions(split, LanguageSplit::kAll).empty());
  CHECK_THROWS_WITH(GenerateInstructions(split, 7, 5, LanguageSplit::kTrain),
                    Catch::Contains("no split template takes the reference 'left'; split "
                                    "instructions use: none, top, along_length"));
  CutSpec ratio = Spec(CutStyle::kSaw, CutState::kRatio, "cucumber", DirectionalReference::kTop);
  ratio.ratio = 0.3;
  CHECK_THROWS_WITH(GenerateInstructions(ratio, 7, 1, LanguageSplit::kAll),
                    Catch::Contains("no ratio template takes the reference 'top'; ratio "
                                    "instructions use: none, left, right, along_length"));
}

TEST_CASE("template files are validated with the path and the place named", "[task][language]") {
  CHECK_THROWS_WITH(LoadInstructionTemplates("/nonexistent/templates.json"),
                    Catch::Contains("/nonexistent/templates.json: cannot be read"));
  CHECK_THROWS_WITH(ParseInstructionTemplates("{not json", "bad.json"),
                    Catch::Contains("bad.json: JSON"));
  const std::string minimal_states = R"({"schema_version": 1, "states": {"middle": {
      "references": ["none"], "templates": [{"text": "{verb} the {object} {amount} {side}",
      "split": "train"}]}}})";
  CHECK_THROWS_WITH(ParseInstructionTemplates(minimal_states, "t.json"),
                    Catch::Contains("states.middle.templates[0]: unknown placeholder {amount}"));
  const std::string bad_split = R"({"schema_version": 1, "states": {"middle": {
      "references": ["none"], "templates": [{"text": "{verb} the {object} {side}",
      "split": "test"}]}}})";
  CHECK_THROWS_WITH(ParseInstructionTemplates(bad_split, "t.json"),
                    Catch::Contains("expected \"train\" or \"held_out\""));
  const std::string bad_reference = R"({"schema_version": 1, "states": {"middle": {
      "references": ["bottom"], "templates": []}}})";
  CHECK_THROWS_WITH(ParseInstructionTemplates(bad_reference, "t.json"),
                    Catch::Contains("unknown directional reference 'bottom'"));
  CHECK(DefaultInstructionTemplates().source == DefaultInstructionTemplatesPath());
}

}  // namespace
}  // namespace culinarycut::task
