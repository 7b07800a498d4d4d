#include "sim/task/instruction_templates.h"

#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "sim/core/assets.h"

namespace culinarycut::task {
namespace {

using nlohmann::json;

constexpr int kSchemaVersion = 1;

// Every error names the file and the JSON location, so a researcher editing the data finds it.
class Checker {
 public:
  explicit Checker(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void Fail(const std::string& where, const std::string& what) const {
    throw TaskError("instruction templates " + source_ + ": " + where + ": " + what);
  }

  const json& Member(const json& object, const std::string& key, const std::string& where) const {
    if (!object.is_object()) Fail(where, "expected an object");
    const auto found = object.find(key);
    if (found == object.end()) Fail(where, "missing \"" + key + "\"");
    return *found;
  }

  const json& NonEmptyArray(const json& object, const std::string& key,
                            const std::string& where) const {
    const json& array = Member(object, key, where);
    if (!array.is_array() || array.empty()) Fail(where + "." + key, "expected a non-empty array");
    return array;
  }

  std::string Text(const json& entry, const std::string& where, bool allow_empty) const {
    const json& text = Member(entry, "text", where);
    if (!text.is_string()) Fail(where + ".text", "expected a string");
    const std::string value = text.get<std::string>();
    if (value.empty() && !allow_empty) Fail(where + ".text", "must not be empty");
    return value;
  }

  PhraseSplit Split(const json& entry, const std::string& where) const {
    const json& split = Member(entry, "split", where);
    if (split == "train") return PhraseSplit::kTrain;
    if (split == "held_out") return PhraseSplit::kHeldOut;
    Fail(where + ".split", "expected \"train\" or \"held_out\", got " + split.dump());
  }

 private:
  std::string source_;
};

// The {name} placeholders in a text, in order; throws on an unclosed brace.
std::vector<std::string> Placeholders(const std::string& text, const Checker& checker,
                                      const std::string& where) {
  std::vector<std::string> names;
  for (size_t open = text.find('{'); open != std::string::npos; open = text.find('{', open + 1)) {
    const size_t close = text.find('}', open);
    if (close == std::string::npos) checker.Fail(where, "unclosed '{' in \"" + text + "\"");
    names.push_back(text.substr(open + 1, close - open - 1));
  }
  return names;
}

void RequireOnly(const std::vector<std::string>& found, const std::set<std::string>& allowed,
                 const Checker& checker, const std::string& where) {
  std::set<std::string> seen;
  for (const auto& name : found) {
    if (!allowed.count(name)) checker.Fail(where, "unknown placeholder {" + name + "}");
    if (!seen.insert(name).second) checker.Fail(where, "placeholder {" + name + "} twice");
  }
}

std::vector<DirectionalReference> References(const json& array, const Checker& checker,
                                             const std::string& where) {
  if (!array.is_array() || array.empty()) checker.Fail(where, "expected a non-empty array");
  std::vector<DirectionalReference> references;
  for (const auto& name : array) {
    if (!name.is_string()) checker.Fail(where, "expected reference names");
    try {
      references.push_back(DirectionalReferenceFromName(name.get<std::string>()));
    } catch (const TaskError& error) {
      checker.Fail(where, error.what());
    }
  }
  return references;
}

std::vector<InstructionTemplate> ParseStateTemplates(const json& states, CutState state,
                                                     const Checker& checker) {
  const std::string where = "states." + Name(state);
  const json& entry = checker.Member(states, Name(state), "states");
  const auto default_references =
      References(checker.Member(entry, "references", where), checker, where + ".references");
  const std::string state_placeholder = state == CutState::kMiddle  ? "middle"
                                        : state == CutState::kRatio ? "quantity"
                                                                    : "pieces";
  std::vector<InstructionTemplate> templates;
  const json& array = checker.NonEmptyArray(entry, "templates", where);
  for (size_t i = 0; i < array.size(); ++i) {
    const std::string at = where + ".templates[" + std::to_string(i) + "]";
    InstructionTemplate parsed;
    parsed.text = checker.Text(array[i], at, false);
    parsed.split = checker.Split(array[i], at);
    parsed.references = array[i].contains("references")
                            ? References(array[i]["references"], checker, at + ".references")
                            : default_references;
    const auto names = Placeholders(parsed.text, checker, at);
    RequireOnly(names, {"verb", "object", "side", state_placeholder}, checker, at);
    if (!parsed.HasPlaceholder("object")) checker.Fail(at, "needs {object}");
    if (!parsed.HasPlaceholder("side")) checker.Fail(at, "needs {side}");
    // A middle template may omit {middle}: naming only the style means a Middle cut.
    if (state != CutState::kMiddle && !parsed.HasPlaceholder(state_placeholder)) {
      checker.Fail(at, "needs {" + state_placeholder + "}");
    }
    templates.push_back(std::move(parsed));
  }
  return templates;
}

// A pool of fixed phrases (verbs, sides, middle phrases): no placeholders, no values.
std::vector<Phrase> ParsePlainPool(const json& array, const Checker& checker,
                                   const std::string& where, bool allow_empty) {
  if (!array.is_array() || array.empty()) checker.Fail(where, "expected a non-empty array");
  std::vector<Phrase> pool;
  for (size_t i = 0; i < array.size(); ++i) {
    const std::string at = where + "[" + std::to_string(i) + "]";
    Phrase phrase;
    phrase.text = checker.Text(array[i], at, allow_empty);
    phrase.split = checker.Split(array[i], at);
    RequireOnly(Placeholders(phrase.text, checker, at), {}, checker, at);
    pool.push_back(std::move(phrase));
  }
  return pool;
}

// A pool whose entries carry a value: [numerator, denominator] for fractions, an integer count.
std::vector<Phrase> ParseValuedPool(const json& array, const Checker& checker,
                                    const std::string& where,
                                    const std::set<std::string>& placeholders, bool fraction_value,
                                    bool value_required) {
  if (!array.is_array() || array.empty()) checker.Fail(where, "expected a non-empty array");
  std::vector<Phrase> pool;
  for (size_t i = 0; i < array.size(); ++i) {
    const std::string at = where + "[" + std::to_string(i) + "]";
    Phrase phrase;
    phrase.text = checker.Text(array[i], at, false);
    phrase.split = checker.Split(array[i], at);
    const auto names = Placeholders(phrase.text, checker, at);
    RequireOnly(names, placeholders, checker, at);
    if (array[i].contains("value")) {
      const json& value = array[i]["value"];
      if (fraction_value) {
        if (!value.is_array() || value.size() != 2 || !value[0].is_number_integer() ||
            !value[1].is_number_integer()) {
          checker.Fail(at + ".value", "expected [numerator, denominator]");
        }
        phrase.numerator = value[0].get<int>();
        phrase.denominator = value[1].get<int>();
        if (phrase.numerator <= 0 || phrase.numerator >= phrase.denominator) {
          checker.Fail(at + ".value", "a ratio must lie strictly between 0 and 1");
        }
      } else {
        if (!value.is_number_integer() || value.get<int>() < 1) {
          checker.Fail(at + ".value", "expected a positive integer");
        }
        phrase.numerator = value.get<int>();
        phrase.denominator = 1;
      }
      if (!names.empty()) checker.Fail(at, "has both a fixed value and a placeholder");
    } else if (value_required || names.empty()) {
      checker.Fail(at, "needs a \"value\" (or a placeholder)");
    }
    pool.push_back(std::move(phrase));
  }
  return pool;
}

}  // namespace

bool InstructionTemplate::HasPlaceholder(const std::string& name) const {
  return text.find("{" + name + "}") != std::string::npos;
}

InstructionTemplates ParseInstructionTemplates(const std::string& json_text,
                                               const std::string& source) {
  const Checker checker(source);
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::parse_error& error) {
    checker.Fail("JSON", error.what());
  }
  const json& version = checker.Member(root, "schema_version", "top level");
  if (version != kSchemaVersion) {
    checker.Fail("schema_version", "expected " + std::to_string(kSchemaVersion) + ", got " +
                                       version.dump());
  }
  InstructionTemplates result;
  result.source = source;
  const json& states = checker.Member(root, "states", "top level");
  for (CutState state : {CutState::kMiddle, CutState::kRatio, CutState::kSplit}) {
    result.templates[static_cast<int>(state)] = ParseStateTemplates(states, state, checker);
  }

  const json& pools = checker.Member(root, "pools", "top level");
  const json& verbs = checker.Member(pools, "verb", "pools");
  result.implicit_verbs =
      ParsePlainPool(checker.Member(verbs, "implicit", "pools.verb"), checker,
                     "pools.verb.implicit", false);
  for (CutStyle style : {CutStyle::kNormal, CutStyle::kBias, CutStyle::kGuillotine,
                         CutStyle::kSaw}) {
    result.style_verbs[static_cast<int>(style)] =
        ParsePlainPool(checker.Member(verbs, Name(style), "pools.verb"), checker,
                       "pools.verb." + Name(style), false);
  }
  const json& sides = checker.Member(pools, "side", "pools");
  for (int i = 0; i < kReferenceCount; ++i) {
    const std::string name = Name(static_cast<DirectionalReference>(i));
    result.sides[i] = ParsePlainPool(checker.Member(sides, name, "pools.side"), checker,
                                     "pools.side." + name, /*allow_empty=*/i == 0);
  }
  result.middle_phrases =
      ParsePlainPool(checker.Member(pools, "middle", "pools"), checker, "pools.middle", false);
  result.quantity_forms = ParseValuedPool(
      checker.Member(pools, "quantity", "pools"), checker, "pools.quantity",
      {"decimal", "percent", "percent_words", "fraction", "slash"}, true, false);
  result.fractions = ParseValuedPool(checker.Member(pools, "fraction", "pools"), checker,
                                     "pools.fraction", {}, true, true);
  result.pieces_forms = ParseValuedPool(checker.Member(pools, "pieces", "pools"), checker,
                                        "pools.pieces", {"count"}, false, false);
  result.counts = ParseValuedPool(checker.Member(pools, "count", "pools"), checker,
                                  "pools.count", {}, false, true);
  return result;
}

InstructionTemplates LoadInstructionTemplates(const std::string& path) {
  std::ifstream file(path);
  if (!file) {
    throw TaskError("instruction templates " + path +
                    ": cannot be read (set CULINARYCUT_ASSETS_DIR to the assets/ folder)");
  }
  std::ostringstream text;
  text << file.rdbuf();
  return ParseInstructionTemplates(text.str(), path);
}

std::string DefaultInstructionTemplatesPath() {
  return AssetsDir() + "/language/instruction_templates.json";
}

const InstructionTemplates& DefaultInstructionTemplates() {
  // A function-local static is initialised once even with concurrent callers (C++11).
  static const InstructionTemplates templates =
      LoadInstructionTemplates(DefaultInstructionTemplatesPath());
  return templates;
}

}  // namespace culinarycut::task
