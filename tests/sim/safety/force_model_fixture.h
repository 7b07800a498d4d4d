// Force-model asset text for tests: a valid file with chosen terms, which tests then break one field at a time.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace culinarycut::testing {

struct TestTerm {
  double coefficient;
  std::vector<double> exponents;  // speed, E, yield stress, toughness, edge length
};

inline nlohmann::json ForceModelDocument(const std::vector<TestTerm>& terms, double top_speed_m_s = 4.0) {
  nlohmann::json document = {
      {"format", "culinarycut.safety.force_model"},
      {"version", 1},
      {"target", "peak_blade_force_n"},
      {"inputs", {"speed_m_s", "youngs_modulus_mpa", "yield_stress_kpa", "fracture_toughness_j_m2", "edge_length_m"}},
      {"ranges",
       {{"speed_m_s", {0.02, top_speed_m_s}},
        {"youngs_modulus_mpa", {0.1, 50.0}},
        {"yield_stress_kpa", {0.0, 500.0}},
        {"fracture_toughness_j_m2", {10.0, 2000.0}},
        {"edge_length_m", {0.005, 0.2}}}},
      {"terms", nlohmann::json::array()},
      {"out_of_range_factor", 1.5},
      {"fit", {{"r2_held_out", 0.9}, {"max_abs_error_n", 2.0}, {"rmse_n", 1.0}, {"samples", 10}, {"held_out", 3},
               {"monotonic_in_speed", true}}},
      {"provenance", {{"quality", "draft"}, {"dataset_sha256", "test"}}}};
  for (const TestTerm& term : terms) document["terms"].push_back({{"coefficient", term.coefficient}, {"exponents", term.exponents}});
  return document;
}

}  // namespace culinarycut::testing
