// Instruction text -> CutSpec, rule-based (docs/language.md, "Parser"). Works on the generated
// language and on plain free text such as "saw the banana into 4 pieces".
#pragma once

#include <string>

#include "sim/task/cut_spec.h"

namespace culinarycut::task {

// What the text says, before the default rules: style and state stay empty when the text does not
// name them, and target_object stays empty when it names no food. Throws TaskError when the text
// is empty or contradicts itself (two foods, two styles, two different quantities, both sides),
// or names a ratio outside [0.1, 0.9] or a split other than 3, 4 or 5 pieces.
PartialCutSpec ParseInstructionPartial(const std::string& text);

// ParseInstructionPartial, then the paper's default rules (style only -> Middle, state only ->
// Normal). Throws TaskError as above, and when no food is named.
CutSpec ParseInstruction(const std::string& text);

}  // namespace culinarycut::task
