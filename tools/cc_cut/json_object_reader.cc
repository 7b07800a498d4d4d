#include "tools/cc_cut/json_object_reader.h"

#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>

namespace culinarycut::cc_cut {

using nlohmann::json;

void FailField(const std::string& field, const std::string& problem) {
  throw std::invalid_argument(field + ": " + problem);
}

std::string JsonTypeName(const json& value) {
  if (value.is_number()) return "a number";
  if (value.is_string()) return "a string";
  if (value.is_boolean()) return "a boolean";
  if (value.is_array()) return "an array";
  if (value.is_object()) return "an object";
  return "null";
}

std::string ShowNumber(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

NumberRange Positive() {
  return {[](double v) { return v > 0.0; }, "> 0"};
}
NumberRange NonNegative() {
  return {[](double v) { return v >= 0.0; }, ">= 0"};
}
NumberRange AnyFinite() {
  return {[](double) { return true; }, "finite"};
}
NumberRange OpenInterval(double low, double high) {
  return {[=](double v) { return v > low && v < high; },
          "in (" + ShowNumber(low) + ", " + ShowNumber(high) + ")"};
}
NumberRange HalfOpenInterval(double low, double high) {
  return {[=](double v) { return v > low && v <= high; },
          "in (" + ShowNumber(low) + ", " + ShowNumber(high) + "]"};
}

JsonObjectReader::JsonObjectReader(const json& object, std::string path)
    : object_(object), path_(std::move(path)) {
  if (!object_.is_object()) {
    FailField(path_.empty() ? "top level" : path_, "expected an object, got " + JsonTypeName(object_));
  }
}

const json* JsonObjectReader::Get(const std::string& key) {
  read_.insert(key);
  const auto it = object_.find(key);
  return it == object_.end() ? nullptr : &*it;
}

bool JsonObjectReader::Number(const std::string& key, double* out, const NumberRange& range) {
  const json* value = Get(key);
  if (value == nullptr) return false;
  if (!value->is_number()) FailField(Field(key), "expected a number, got " + JsonTypeName(*value));
  const double number = value->get<double>();
  if (!std::isfinite(number) || !range.contains(number)) {
    FailField(Field(key), "must be " + range.description + ", got " + ShowNumber(number));
  }
  *out = number;
  return true;
}

bool JsonObjectReader::Number(const std::string& key, std::optional<double>* out,
                              const NumberRange& range) {
  double number = 0.0;
  if (!Number(key, &number, range)) return false;
  *out = number;
  return true;
}

bool JsonObjectReader::Integer(const std::string& key, int* out, int min_value, int max_value) {
  const json* value = Get(key);
  if (value == nullptr) return false;
  if (!value->is_number_integer()) {
    FailField(Field(key), "expected an integer, got " + JsonTypeName(*value));
  }
  const auto number = value->get<std::int64_t>();
  if (number < min_value || number > max_value) {
    FailField(Field(key), "must be in [" + std::to_string(min_value) + ", " +
                              std::to_string(max_value) + "], got " + std::to_string(number));
  }
  *out = static_cast<int>(number);
  return true;
}

bool JsonObjectReader::Integer(const std::string& key, std::optional<int>* out, int min_value,
                               int max_value) {
  int number = 0;
  if (!Integer(key, &number, min_value, max_value)) return false;
  *out = number;
  return true;
}

bool JsonObjectReader::Bool(const std::string& key, bool* out) {
  const json* value = Get(key);
  if (value == nullptr) return false;
  if (!value->is_boolean()) {
    FailField(Field(key), "expected true or false, got " + JsonTypeName(*value));
  }
  *out = value->get<bool>();
  return true;
}

bool JsonObjectReader::Bool(const std::string& key, std::optional<bool>* out) {
  bool flag = false;
  if (!Bool(key, &flag)) return false;
  *out = flag;
  return true;
}

bool JsonObjectReader::String(const std::string& key, std::string* out) {
  const json* value = Get(key);
  if (value == nullptr) return false;
  if (!value->is_string()) FailField(Field(key), "expected a string, got " + JsonTypeName(*value));
  *out = value->get<std::string>();
  return true;
}

std::vector<double> JsonObjectReader::Numbers(const std::string& key, std::size_t size) {
  const json* value = Get(key);
  if (value == nullptr) return {};
  const std::string expected = "expected an array of " + std::to_string(size) + " finite numbers";
  if (!value->is_array() || value->size() != size) {
    FailField(Field(key), expected + ", got " + JsonTypeName(*value) +
                              (value->is_array() ? " of " + std::to_string(value->size()) : ""));
  }
  std::vector<double> numbers;
  for (const json& element : *value) {
    if (!element.is_number() || !std::isfinite(element.get<double>())) FailField(Field(key), expected);
    numbers.push_back(element.get<double>());
  }
  return numbers;
}

const json* JsonObjectReader::Object(const std::string& key) {
  const json* value = Get(key);
  if (value != nullptr && !value->is_object()) {
    FailField(Field(key), "expected an object, got " + JsonTypeName(*value));
  }
  return value;
}

void JsonObjectReader::Finish(const std::vector<std::pair<std::string, std::string>>& hints) const {
  for (const auto& item : object_.items()) {
    if (read_.count(item.key()) != 0) continue;
    std::string problem = "unknown key";
    for (const auto& [old_key, now] : hints) {
      if (old_key == item.key()) problem += " (" + now + ")";
    }
    FailField(Field(item.key()), problem);
  }
}

}  // namespace culinarycut::cc_cut
