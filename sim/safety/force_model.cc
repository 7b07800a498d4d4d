#include "sim/safety/force_model.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "sim/core/assets.h"

namespace culinarycut::safety {
namespace {

using nlohmann::json;

[[noreturn]] void Fail(const std::string& field, const std::string& problem) {
  throw ForceModelError(field + " " + problem);
}

const json& Member(const json& object, const char* key, const std::string& field) {
  const auto found = object.find(key);
  if (found == object.end()) Fail(field, "is missing");
  return *found;
}

// A finite number (JSON cannot hold NaN, but 1e999 reads as infinity).
double FiniteNumber(const json& value, const std::string& field) {
  if (!value.is_number()) Fail(field, "must be a number");
  const double number = value.get<double>();
  if (!std::isfinite(number)) Fail(field, "must be finite");
  return number;
}

std::string Text(const json& object, const char* key) {
  const auto found = object.find(key);
  return found != object.end() && found->is_string() ? found->get<std::string>() : std::string();
}

void ReadInputs(const json& root, ForceModel* model) {
  const json& inputs = Member(root, "inputs", "inputs");
  bool matches = inputs.is_array() && inputs.size() == kForceInputCount;
  for (int j = 0; matches && j < kForceInputCount; ++j) {
    matches = inputs[j].is_string() && inputs[j].get<std::string>() == kForceInputNames[j];
  }
  if (!matches) {
    Fail("inputs", "must be [\"speed_m_s\", \"youngs_modulus_mpa\", \"yield_stress_kpa\", "
                   "\"fracture_toughness_j_m2\", \"edge_length_m\"] in this order");
  }
  const json& ranges = Member(root, "ranges", "ranges");
  if (!ranges.is_object()) Fail("ranges", "must be an object of [low, high] per input");
  for (int j = 0; j < kForceInputCount; ++j) {
    const std::string field = std::string("ranges.") + kForceInputNames[j];
    const json& range = Member(ranges, kForceInputNames[j], field);
    if (!range.is_array() || range.size() != 2) Fail(field, "must be [low, high]");
    const double low = FiniteNumber(range[0], field + "[0]");
    const double high = FiniteNumber(range[1], field + "[1]");
    if (low < 0.0 || high <= low) Fail(field, "must have 0 <= low < high");
    model->ranges[j] = InputRange{low, high};
  }
}

void ReadTerms(const json& root, ForceModel* model) {
  const json& terms = Member(root, "terms", "terms");
  if (!terms.is_array() || terms.empty()) Fail("terms", "must be a non-empty array of {coefficient, exponents}");
  for (std::size_t k = 0; k < terms.size(); ++k) {
    const std::string field = "terms[" + std::to_string(k) + "]";
    if (!terms[k].is_object()) Fail(field, "must be an object {coefficient, exponents}");
    ForceTerm term;
    term.coefficient = FiniteNumber(Member(terms[k], "coefficient", field + ".coefficient"), field + ".coefficient");
    // Negative coefficients or exponents would break the monotonicity in speed that v_safe relies on.
    if (term.coefficient < 0.0) Fail(field + ".coefficient", "must be >= 0 (the model is a posynomial)");
    const json& exponents = Member(terms[k], "exponents", field + ".exponents");
    if (!exponents.is_array() || exponents.size() != kForceInputCount) {
      Fail(field + ".exponents", "must have " + std::to_string(kForceInputCount) + " numbers, one per input");
    }
    for (int j = 0; j < kForceInputCount; ++j) {
      const std::string exponent_field = field + ".exponents[" + std::to_string(j) + "]";
      term.exponents[j] = FiniteNumber(exponents[j], exponent_field);
      if (term.exponents[j] < 0.0) Fail(exponent_field, "must be >= 0 (the model is a posynomial)");
    }
    model->terms.push_back(term);
  }
}

void ReadFit(const json& root, ForceModel* model) {
  const json& fit = Member(root, "fit", "fit");
  if (!fit.is_object()) Fail("fit", "must be an object");
  model->fit.r2_held_out = FiniteNumber(Member(fit, "r2_held_out", "fit.r2_held_out"), "fit.r2_held_out");
  model->fit.max_abs_error_n = FiniteNumber(Member(fit, "max_abs_error_n", "fit.max_abs_error_n"), "fit.max_abs_error_n");
  model->fit.rmse_n = FiniteNumber(Member(fit, "rmse_n", "fit.rmse_n"), "fit.rmse_n");
  for (auto [key, slot] : {std::pair{"samples", &model->fit.samples}, std::pair{"held_out", &model->fit.held_out}}) {
    const json& count = Member(fit, key, std::string("fit.") + key);
    if (!count.is_number_integer() || count.get<std::int64_t>() < 0) Fail(std::string("fit.") + key, "must be a count >= 0");
    *slot = count.get<std::int64_t>();
  }
  if (const auto monotonic = fit.find("monotonic_in_speed"); monotonic != fit.end()) {
    if (!monotonic->is_boolean()) Fail("fit.monotonic_in_speed", "must be true or false");
    model->fit.monotonic_in_speed = monotonic->get<bool>();
  }
}

}  // namespace

ForceModel ParseForceModel(const std::string& json_text) {
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::exception& error) {  // a syntax error, or a number past a double (1e999)
    throw ForceModelError(std::string("is not valid JSON: ") + error.what());
  }
  if (!root.is_object()) Fail("(top level)", "must be a JSON object");
  const json& format = Member(root, "format", "format");
  if (!format.is_string() || format.get<std::string>() != kForceModelFormat) {
    Fail("format", std::string("must be \"") + kForceModelFormat + "\"");
  }
  const json& version = Member(root, "version", "version");
  if (!version.is_number_integer() || version.get<std::int64_t>() != kForceModelVersion) {
    Fail("version", "is " + version.dump() + "; this reader knows version " + std::to_string(kForceModelVersion));
  }
  const json& target = Member(root, "target", "target");
  if (!target.is_string() || target.get<std::string>() != "peak_blade_force_n") Fail("target", "must be \"peak_blade_force_n\"");
  ForceModel model;
  ReadInputs(root, &model);
  ReadTerms(root, &model);
  model.out_of_range_factor = FiniteNumber(Member(root, "out_of_range_factor", "out_of_range_factor"), "out_of_range_factor");
  if (model.out_of_range_factor < 1.0) Fail("out_of_range_factor", "must be >= 1 (outside the ranges the model is conservative)");
  ReadFit(root, &model);
  if (const auto provenance = root.find("provenance"); provenance != root.end() && provenance->is_object()) {
    model.quality = Text(*provenance, "quality");
    model.dataset_sha256 = Text(*provenance, "dataset_sha256");
  }
  return model;
}

ForceModel LoadForceModel(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw ForceModelError(path + ": cannot be read (missing?)");
  std::ostringstream text;
  text << file.rdbuf();
  try {
    ForceModel model = ParseForceModel(text.str());
    model.source = path;
    return model;
  } catch (const ForceModelError& error) {
    throw ForceModelError(path + ": " + error.what());
  }
}

std::string DefaultForceModelPath() { return AssetsDir() + "/safety/force_model.json"; }

ForcePrediction PredictPeakForce(const ForceModel& model, double speed_m_s, const CutMaterial& material) {
  const std::array<double, kForceInputCount> x = {speed_m_s, material.youngs_modulus_mpa, material.yield_stress_kpa,
                                                  material.fracture_toughness_j_m2, material.edge_length_m};
  ForcePrediction prediction;
  for (int j = 0; j < kForceInputCount; ++j) {
    prediction.out_of_range |= x[j] < model.ranges[j].low || x[j] > model.ranges[j].high;
  }
  for (const ForceTerm& term : model.terms) {
    double product = term.coefficient;
    for (int j = 0; j < kForceInputCount; ++j) {
      if (term.exponents[j] != 0.0) product *= std::pow(x[j], term.exponents[j]);
    }
    prediction.force_n += product;
  }
  if (prediction.out_of_range) prediction.force_n *= model.out_of_range_factor;
  return prediction;
}

}  // namespace culinarycut::safety
