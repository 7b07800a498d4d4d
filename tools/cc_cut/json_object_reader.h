// Reads the members of one JSON object by name, each checked for type and range; Finish() rejects
// the keys nobody read. Every error is a std::invalid_argument naming the field: "knife.settle_s:
// must be >= 0, got -0.1".
#pragma once

#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace culinarycut::cc_cut {

[[noreturn]] void FailField(const std::string& field, const std::string& problem);

// "a number", "a string", "an array", ... for messages.
std::string JsonTypeName(const nlohmann::json& value);

// A number as people write it ("0.5", "1e+06").
std::string ShowNumber(double value);

// A check on a number and how a message describes it, e.g. {[](double v) { return v > 0; }, "> 0"}.
struct NumberRange {
  std::function<bool(double)> contains;
  std::string description;
};
NumberRange Positive();
NumberRange NonNegative();
NumberRange AnyFinite();
NumberRange OpenInterval(double low, double high);       // (low, high)
NumberRange HalfOpenInterval(double low, double high);   // (low, high]

class JsonObjectReader {
 public:
  // `path` names the object in messages ("knife", "solver.cutting"); "" is the top level.
  JsonObjectReader(const nlohmann::json& object, std::string path);

  bool Has(const std::string& key) const { return object_.contains(key); }
  std::string Field(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  // Each returns whether the key was present; absent keys leave `out` as it was.
  bool Number(const std::string& key, double* out, const NumberRange& range);
  bool Number(const std::string& key, std::optional<double>* out, const NumberRange& range);
  bool Integer(const std::string& key, int* out, int min_value, int max_value);
  bool Integer(const std::string& key, std::optional<int>* out, int min_value, int max_value);
  bool Bool(const std::string& key, bool* out);
  bool Bool(const std::string& key, std::optional<bool>* out);
  bool String(const std::string& key, std::string* out);
  // An array of exactly `size` finite numbers.
  std::vector<double> Numbers(const std::string& key, std::size_t size);
  // A nested object, or nullptr when absent.
  const nlohmann::json* Object(const std::string& key);

  // Fails on the first key nothing read; `hints` maps a key to where it went, for files of an
  // older schema.
  void Finish(const std::vector<std::pair<std::string, std::string>>& hints = {}) const;

 private:
  const nlohmann::json* Get(const std::string& key);

  const nlohmann::json& object_;
  std::string path_;
  std::set<std::string> read_;
};

}  // namespace culinarycut::cc_cut
