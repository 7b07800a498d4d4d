#include "sim/task/instruction_generator.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <random>
#include <unordered_map>

namespace culinarycut::task {
namespace {

// A phrase chosen for one placeholder; an instruction is held out if any of its parts is.
struct Part {
  std::string text;
  bool held_out = false;
};

struct Fraction {
  int numerator = 0;
  int denominator = 1;
};

bool SameValue(const Fraction& value, int numerator, int denominator) {
  return static_cast<long>(value.numerator) * denominator ==
         static_cast<long>(numerator) * value.denominator;
}

// The ratio as the smallest exact fraction n/d (d <= 100); throws when it is none of those.
Fraction AsFraction(double ratio) {
  for (int denominator = 1; denominator <= 100; ++denominator) {
    const double scaled = ratio * denominator;
    if (std::abs(scaled - std::round(scaled)) < 1e-9 * denominator) {
      return {static_cast<int>(std::round(scaled)), denominator};
    }
  }
  throw TaskError("ratio " + std::to_string(ratio) +
                  " has no exact wording; the generator covers fractions with denominator <= 100");
}

std::string NumberWords(int number) {
  static const char* kUnits[] = {"zero",    "one",     "two",       "three",    "four",
                                 "five",    "six",     "seven",     "eight",    "nine",
                                 "ten",     "eleven",  "twelve",    "thirteen", "fourteen",
                                 "fifteen", "sixteen", "seventeen", "eighteen", "nineteen"};
  static const char* kTens[] = {"", "", "twenty", "thirty", "forty",
                                "fifty", "sixty", "seventy", "eighty", "ninety"};
  if (number < 20) return kUnits[number];
  const std::string tens = kTens[number / 10];
  return number % 10 == 0 ? tens : tens + "-" + kUnits[number % 10];
}

// Replaces the {placeholder} in `form` (there is at most one) with `value`.
std::string Fill(const std::string& form, const std::string& placeholder,
                 const std::string& value) {
  const std::string key = "{" + placeholder + "}";
  const size_t at = form.find(key);
  if (at == std::string::npos) return form;
  return form.substr(0, at) + value + form.substr(at + key.size());
}

// Every exact wording of the ratio: a form is used only when its value is exactly the ratio.
std::vector<Part> QuantityParts(const InstructionTemplates& templates, double ratio) {
  const Fraction value = AsFraction(ratio);
  const bool per_hundred = 100 % value.denominator == 0;
  const int percent = per_hundred ? value.numerator * (100 / value.denominator) : 0;
  const std::string decimal = percent % 10 == 0
                                  ? "0." + std::to_string(percent / 10)
                                  : (percent < 10 ? "0.0" : "0.") + std::to_string(percent);
  std::vector<Part> parts;
  for (const Phrase& form : templates.quantity_forms) {
    const bool held_out = form.split == PhraseSplit::kHeldOut;
    if (form.HasValue()) {
      if (SameValue(value, form.numerator, form.denominator)) {
        parts.push_back({form.text, held_out});
      }
    } else if (form.text.find("{fraction}") != std::string::npos) {
      for (const Phrase& fraction : templates.fractions) {
        if (!SameValue(value, fraction.numerator, fraction.denominator)) continue;
        parts.push_back({Fill(form.text, "fraction", fraction.text),
                         held_out || fraction.split == PhraseSplit::kHeldOut});
      }
    } else if (form.text.find("{slash}") != std::string::npos) {
      parts.push_back({Fill(form.text, "slash", std::to_string(value.numerator) + "/" +
                                                    std::to_string(value.denominator)),
                       held_out});
    } else if (per_hundred) {
      std::string text = Fill(form.text, "decimal", decimal);
      text = Fill(text, "percent", std::to_string(percent));
      text = Fill(text, "percent_words", NumberWords(percent));
      parts.push_back({text, held_out});
    }
  }
  return parts;
}

std::vector<Part> PiecesParts(const InstructionTemplates& templates, int pieces) {
  std::vector<Part> parts;
  for (const Phrase& form : templates.pieces_forms) {
    const bool held_out = form.split == PhraseSplit::kHeldOut;
    if (form.HasValue()) {
      if (form.numerator == pieces) parts.push_back({form.text, held_out});
      continue;
    }
    for (const Phrase& count : templates.counts) {
      if (count.numerator != pieces) continue;
      parts.push_back(
          {Fill(form.text, "count", count.text), held_out || count.split == PhraseSplit::kHeldOut});
    }
  }
  return parts;
}

std::vector<Part> PlainParts(const std::vector<Phrase>& pool) {
  std::vector<Part> parts;
  for (const Phrase& phrase : pool) {
    parts.push_back({phrase.text, phrase.split == PhraseSplit::kHeldOut});
  }
  return parts;
}

std::vector<Part> VerbParts(const InstructionTemplates& templates, CutStyle style) {
  std::vector<Part> parts;
  // A plain "cut"/"slice" names no style; the default rule makes it Normal.
  if (style == CutStyle::kNormal) parts = PlainParts(templates.implicit_verbs);
  for (const Part& part : PlainParts(templates.style_verbs[static_cast<int>(style)])) {
    parts.push_back(part);
  }
  return parts;
}

// Phrases for the template's state placeholder ({middle}, {quantity} or {pieces}).
std::vector<Part> PositionParts(const InstructionTemplates& templates,
                                const InstructionTemplate& instruction_template,
                                const CutSpec& spec) {
  switch (spec.state) {
    case CutState::kMiddle:
      if (!instruction_template.HasPlaceholder("middle")) return {{"", false}};
      return PlainParts(templates.middle_phrases);
    case CutState::kRatio:
      return QuantityParts(templates, spec.ratio);
    case CutState::kSplit:
      return PiecesParts(templates, spec.split_pieces);
  }
  return {};
}

// Single spaces, no space before a comma, no leading or trailing space, a capital first letter.
std::string Tidy(const std::string& raw) {
  std::string text;
  text.reserve(raw.size());
  for (char c : raw) {
    if (c == ' ' && (text.empty() || text.back() == ' ')) continue;
    if (c == ',' && !text.empty() && text.back() == ' ') text.pop_back();
    text.push_back(c);
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  if (!text.empty()) text[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
  return text;
}

std::string Expand(const std::string& text, const std::string& verb, const std::string& object,
                   const std::string& position, const std::string& side) {
  std::string out;
  out.reserve(text.size() + 64);
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '{') {
      out.push_back(text[i]);
      continue;
    }
    const size_t close = text.find('}', i);
    const std::string name = text.substr(i + 1, close - i - 1);
    if (name == "verb") {
      out += verb;
    } else if (name == "object") {
      out += object;
    } else if (name == "side") {
      out += side;
    } else {
      out += position;  // middle, quantity or pieces: validated to be the state's own
    }
    i = close;
  }
  return Tidy(out);
}

bool Allows(const InstructionTemplate& instruction_template, DirectionalReference reference) {
  const auto& references = instruction_template.references;
  return std::find(references.begin(), references.end(), reference) != references.end();
}

// Whether some template of `state` can word a spec of this style and reference (a template
// without {verb} only describes Normal).
bool Carries(const InstructionTemplates& templates, CutState state, CutStyle style,
             DirectionalReference reference) {
  const auto& candidates = templates.For(state);
  return std::any_of(candidates.begin(), candidates.end(), [&](const auto& candidate) {
    return Allows(candidate, reference) &&
           (style == CutStyle::kNormal || candidate.HasPlaceholder("verb"));
  });
}

}  // namespace

std::vector<LabelledInstruction> EnumerateLabelledInstructions(
    const CutSpec& spec, const InstructionTemplates& templates) {
  ValidateCutSpec(spec);
  const std::vector<Part> verbs = VerbParts(templates, spec.style);
  const std::vector<Part> sides = PlainParts(templates.sides[static_cast<int>(spec.reference)]);
  std::vector<LabelledInstruction> instructions;
  std::unordered_map<std::string, size_t> index_of;
  for (const InstructionTemplate& instruction_template : templates.For(spec.state)) {
    if (!Allows(instruction_template, spec.reference)) continue;
    const bool has_verb = instruction_template.HasPlaceholder("verb");
    // A template without {verb} names no style, so it only describes the default (Normal).
    if (!has_verb && spec.style != CutStyle::kNormal) continue;
    const std::vector<Part> template_verbs = has_verb ? verbs : std::vector<Part>{{"", false}};
    const std::vector<Part> positions = PositionParts(templates, instruction_template, spec);
    const bool template_held_out = instruction_template.split == PhraseSplit::kHeldOut;
    for (const Part& verb : template_verbs) {
      for (const Part& position : positions) {
        for (const Part& side : sides) {
          std::string text = Expand(instruction_template.text, verb.text, spec.target_object,
                                    position.text, side.text);
          const bool held_out =
              template_held_out || verb.held_out || position.held_out || side.held_out;
          const LanguageSplit split = held_out ? LanguageSplit::kHeldOut : LanguageSplit::kTrain;
          const auto [found, inserted] = index_of.emplace(text, instructions.size());
          if (inserted) {
            instructions.push_back({std::move(text), split});
          } else if (split == LanguageSplit::kTrain) {
            // A string that train language can produce is train, so the sets stay disjoint.
            instructions[found->second].split = LanguageSplit::kTrain;
          }
        }
      }
    }
  }
  return instructions;
}

std::vector<std::string> EnumerateInstructions(const CutSpec& spec, LanguageSplit split,
                                               const InstructionTemplates& templates) {
  std::vector<std::string> texts;
  for (auto& instruction : EnumerateLabelledInstructions(spec, templates)) {
    if (split == LanguageSplit::kAll || instruction.split == split) {
      texts.push_back(std::move(instruction.text));
    }
  }
  return texts;
}

std::vector<std::string> GenerateInstructions(const CutSpec& spec, std::uint64_t seed, int count,
                                              LanguageSplit split,
                                              const InstructionTemplates& templates) {
  std::vector<std::string> pool = EnumerateInstructions(spec, split, templates);
  if (pool.empty() && count > 0) {
    // Most likely a reference the state's templates never carry (a split "from the left").
    std::string accepted;
    bool takes_reference = false;
    for (int r = 0; r < kReferenceCount; ++r) {
      const auto reference = static_cast<DirectionalReference>(r);
      if (!Carries(templates, spec.state, spec.style, reference)) continue;
      accepted += (accepted.empty() ? "" : ", ") + Name(reference);
      takes_reference = takes_reference || reference == spec.reference;
    }
    if (!takes_reference) {
      throw TaskError("cannot draw " + std::to_string(count) + " instructions for '" +
                      Describe(spec) + "': no " + Name(spec.state) +
                      " template takes the reference '" + Name(spec.reference) + "'; " +
                      Name(spec.state) + " instructions use: " +
                      (accepted.empty() ? std::string("no reference at all") : accepted));
    }
  }
  if (count < 0 || static_cast<size_t>(count) > pool.size()) {
    throw TaskError("cannot draw " + std::to_string(count) + " distinct instructions for '" +
                    Describe(spec) + "': the templates give " + std::to_string(pool.size()));
  }
  // Partial Fisher-Yates with an explicit modulo: mt19937_64's output is fixed by the standard,
  // std::uniform_int_distribution's is not.
  std::mt19937_64 random(seed);
  for (int i = 0; i < count; ++i) {
    const std::uint64_t remaining = pool.size() - static_cast<size_t>(i);
    std::swap(pool[i], pool[i + static_cast<size_t>(random() % remaining)]);
  }
  pool.resize(static_cast<size_t>(count));
  return pool;
}

const std::vector<double>& TaskRatios() {
  static const std::vector<double> ratios = {0.1, 0.2,  0.3,  0.4,       0.5,      0.6,      0.7,
                                             0.8, 0.9, 0.25, 0.75, 1.0 / 3.0, 2.0 / 3.0};
  return ratios;
}

std::vector<CutSpec> EnumerateTaskSpecs(const InstructionTemplates& templates) {
  std::vector<CutSpec> specs;
  for (const std::string& food : KnownFoods()) {
    for (CutStyle style :
         {CutStyle::kNormal, CutStyle::kBias, CutStyle::kGuillotine, CutStyle::kSaw}) {
      for (CutState state : {CutState::kMiddle, CutState::kRatio, CutState::kSplit}) {
        std::vector<double> ratios = {0.5};
        std::vector<int> pieces = {3};
        if (state == CutState::kRatio) ratios = TaskRatios();
        if (state == CutState::kSplit) pieces = {3, 4, 5};
        for (int r = 0; r < kReferenceCount; ++r) {
          const auto reference = static_cast<DirectionalReference>(r);
          if (!Carries(templates, state, style, reference)) continue;
          for (double ratio : ratios) {
            for (int count : pieces) {
              CutSpec spec;
              spec.style = style;
              spec.state = state;
              spec.ratio = ratio;
              spec.split_pieces = count;
              spec.target_object = food;
              spec.reference = reference;
              specs.push_back(spec);
            }
          }
        }
      }
    }
  }
  return specs;
}

}  // namespace culinarycut::task
