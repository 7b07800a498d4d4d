// The instruction templates and lexical pools, loaded from
// assets/language/instruction_templates.json (docs/language.md: layout, train/held-out split).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "sim/task/cut_spec.h"

namespace culinarycut::task {

// Which language set a template or phrase belongs to; held-out language is for evaluation only.
enum class PhraseSplit { kTrain, kHeldOut };

// One template or pool phrase. `numerator`/`denominator` hold a fixed value where the data gives
// one (a fraction word, "halfway", "into thirds"); both are 0 where the value comes from a
// placeholder ({decimal}, {count}, ...).
struct Phrase {
  std::string text;
  PhraseSplit split = PhraseSplit::kTrain;
  int numerator = 0;
  int denominator = 0;
  bool HasValue() const { return denominator > 0; }
};

struct InstructionTemplate {
  std::string text;
  PhraseSplit split = PhraseSplit::kTrain;
  std::vector<DirectionalReference> references;  // the references this template may carry
  bool HasPlaceholder(const std::string& name) const;
};

inline constexpr int kCutStateCount = 3;   // kMiddle, kRatio, kSplit
inline constexpr int kCutStyleCount = 4;   // kNormal, kBias, kGuillotine, kSaw
inline constexpr int kReferenceCount = 5;  // kNone .. kAlongLength

struct InstructionTemplates {
  std::string source;  // file path, for messages
  std::array<std::vector<InstructionTemplate>, kCutStateCount> templates;  // by CutState
  std::vector<Phrase> implicit_verbs;                           // style unnamed: Normal by default
  std::array<std::vector<Phrase>, kCutStyleCount> style_verbs;  // by CutStyle, style named
  std::array<std::vector<Phrase>, kReferenceCount> sides;       // by DirectionalReference
  std::vector<Phrase> middle_phrases;
  std::vector<Phrase> quantity_forms;
  std::vector<Phrase> fractions;     // word fractions with their exact value
  std::vector<Phrase> pieces_forms;  // numerator = piece count where fixed ("into thirds")
  std::vector<Phrase> counts;        // numerator = piece count

  const std::vector<InstructionTemplate>& For(CutState state) const {
    return templates[static_cast<int>(state)];
  }
};

// Parses and validates the JSON text; `source` names it in errors. Throws TaskError saying what is
// wrong and where (e.g. "states.ratio.templates[3]: unknown placeholder {amount}").
InstructionTemplates ParseInstructionTemplates(const std::string& json_text,
                                               const std::string& source);

// Reads and parses a file; throws TaskError naming the path when it cannot be read or is invalid.
InstructionTemplates LoadInstructionTemplates(const std::string& path);

// AssetsDir() + "/language/instruction_templates.json", loaded once (thread-safe) and kept.
const InstructionTemplates& DefaultInstructionTemplates();
std::string DefaultInstructionTemplatesPath();

}  // namespace culinarycut::task
