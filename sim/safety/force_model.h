// The paper's force regression R(v, m): the peak cutting force on the blade predicted from the knife's
// speed and the food's material, fitted on simulator data and read from an asset file. The model is a
// posynomial, F_hat = sum_k c_k prod_j x_j^e_kj with c, e >= 0, so it never decreases with speed
// (docs/safety.md has the file format).
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace culinarycut::safety {

// The model's inputs, in the asset's order and units.
enum class ForceInput { kSpeed = 0, kYoungsModulus, kYieldStress, kFractureToughness, kEdgeLength };
inline constexpr int kForceInputCount = 5;
inline constexpr std::array<const char*, kForceInputCount> kForceInputNames = {
    "speed_m_s", "youngs_modulus_mpa", "yield_stress_kpa", "fracture_toughness_j_m2", "edge_length_m"};
inline constexpr const char* kForceModelFormat = "culinarycut.safety.force_model";
inline constexpr int kForceModelVersion = 1;

// The food under the knife, in the model's units (the speed is the other input).
struct CutMaterial {
  double youngs_modulus_mpa = 0.0;
  double yield_stress_kpa = 0.0;
  double fracture_toughness_j_m2 = 0.0;
  double edge_length_m = 0.0;  // blade edge in the food: the food's extent along the blade
};

struct ForceTerm {
  double coefficient = 0.0;                         // N per unit of the inputs' product
  std::array<double, kForceInputCount> exponents{};  // one per input
};

struct InputRange {
  double low = 0.0;
  double high = 0.0;
};

// How well the fit predicts held-out simulator runs (reported, never used to predict).
struct ForceModelFit {
  double r2_held_out = 0.0;
  double max_abs_error_n = 0.0;
  double rmse_n = 0.0;
  std::int64_t samples = 0;
  std::int64_t held_out = 0;
  bool monotonic_in_speed = true;
};

struct ForceModel {
  int version = kForceModelVersion;
  std::array<InputRange, kForceInputCount> ranges{};  // where the fit was validated
  std::vector<ForceTerm> terms;
  double out_of_range_factor = 1.0;  // >= 1: outside the ranges the prediction is scaled up
  ForceModelFit fit;
  std::string quality;         // provenance.quality: the MPM preset the data came from
  std::string dataset_sha256;  // provenance.dataset_sha256
  std::string source;          // the file it was read from, for messages
};

struct ForcePrediction {
  double force_n = 0.0;
  bool out_of_range = false;  // some input outside its validated range: force_n includes the factor
};

// A file that is not a force model this reader knows; the message names the JSON field at fault.
class ForceModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses and validates the asset's JSON text. Throws ForceModelError naming the field (format,
// version, inputs, ranges.<input>, terms[k].coefficient, terms[k].exponents, out_of_range_factor, fit.*).
ForceModel ParseForceModel(const std::string& json_text);
// Reads and parses a file; the error message starts with the path.
ForceModel LoadForceModel(const std::string& path);
// Where the installed asset lives: <assets>/safety/force_model.json.
std::string DefaultForceModelPath();

// F_hat at this speed for this material (the paper's regression R(v, m)).
ForcePrediction PredictPeakForce(const ForceModel& model, double speed_m_s, const CutMaterial& material);

}  // namespace culinarycut::safety
