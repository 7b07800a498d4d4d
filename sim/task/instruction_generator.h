// Language instructions for a cut spec, from the templates and lexical pools in
// assets/language/instruction_templates.json (paper, "Language Instructions"; docs/language.md).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/task/cut_spec.h"
#include "sim/task/instruction_templates.h"

namespace culinarycut::task {

// kTrain: only train templates and phrases. kHeldOut: at least one held-out template or phrase
// (unseen-language evaluation); never a string that kTrain also produces. kAll: both.
enum class LanguageSplit { kTrain, kHeldOut, kAll };

struct LabelledInstruction {
  std::string text;
  LanguageSplit split = LanguageSplit::kTrain;  // kTrain or kHeldOut
};

// Every distinct instruction for `spec`, each labelled, in a deterministic order (template,
// verb, position phrase, side). Throws TaskError for an invalid spec.
std::vector<LabelledInstruction> EnumerateLabelledInstructions(
    const CutSpec& spec, const InstructionTemplates& templates = DefaultInstructionTemplates());

// The texts of EnumerateLabelledInstructions() that belong to `split`, in the same order.
std::vector<std::string> EnumerateInstructions(
    const CutSpec& spec, LanguageSplit split,
    const InstructionTemplates& templates = DefaultInstructionTemplates());

// `count` distinct instructions drawn from EnumerateInstructions(spec, split) with a local
// std::mt19937_64 seeded by `seed` (partial Fisher-Yates, explicit modulo: the same list on every
// platform). Throws TaskError when fewer than `count` exist; when the state's templates never
// carry the spec's reference (a split "from the left"), the message lists the ones they do.
std::vector<std::string> GenerateInstructions(
    const CutSpec& spec, std::uint64_t seed, int count, LanguageSplit split,
    const InstructionTemplates& templates = DefaultInstructionTemplates());

// The ratios the generator covers: 0.1..0.9 in steps of 0.1, then 0.25, 0.75, 1/3, 2/3.
const std::vector<double>& TaskRatios();

// The task space: 7 foods x 4 styles x {middle; every TaskRatios() value; 3-, 4-, 5-way split}
// x every directional reference some template of that state allows.
std::vector<CutSpec> EnumerateTaskSpecs(
    const InstructionTemplates& templates = DefaultInstructionTemplates());

}  // namespace culinarycut::task
