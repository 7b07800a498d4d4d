#include "sim/mpm/materials.h"

#include <cmath>
#include <stdexcept>

namespace culinarycut::mpm {
namespace {

// Presets. Bulk values from the literature where it has them (cited per preset below);
// "chosen" where it does not. Yield stresses set plastic flow near the failure stress. Friction on
// the board is chosen equal to the knife's until it is measured.
std::vector<Material> Presets() {
  auto make = [](const char* name, double E_pa, double nu, double rho, double yield_pa,
                 double friction, double toughness_j_m2, const char* source) {
    Material m;
    m.name = name;
    m.youngs_modulus_pa = E_pa;
    m.poisson_ratio = nu;
    m.density_kg_m3 = rho;
    m.yield_stress_pa = yield_pa;
    m.friction_coefficient = friction;
    m.board_friction_coefficient = friction;
    m.fracture_toughness_j_m2 = toughness_j_m2;
    m.source = source;
    return m;
  };
  return {
      make("apple", 3.0e6, 0.17, 787.0, 0.35e6, 0.5, 200.0,
           "E 3.0 MPa as simulated by DiSECt (NVlabs); nu 0.17, rho 787 kg/m^3; failure stress "
           "0.32-0.37 MPa (Chakespari et al.); toughness chosen (no reference to calibrate it against)"),
      make("cucumber", 2.5e6, 0.37, 1000.0, 0.3e6, 0.5, 488.0,
           "E 2.5 MPa, nu 0.37, rho 940-1100 kg/m^3, friction 0.5 (Jamdagni & Jia, IROS 2019; their "
           "measured toughness 125 J/m^2); edge toughness 488 J/m^2 calibrated against DiSECt's LS-DYNA "
           "cucumber half-cylinder (bench/lsdyna_calibration.py); yield chosen"),
      make("potato", 2.0e6, 0.45, 630.0, 0.3e6, 0.6, 374.0,
           "E 2.0 MPa, nu 0.45, friction 0.6 (Jamdagni & Jia, IROS 2019; their measured toughness 75 "
           "J/m^2); rho 630 kg/m^3 as simulated by DiSECt (NVlabs); edge toughness 374 J/m^2 calibrated "
           "against DiSECt's LS-DYNA potato prism (bench/lsdyna_calibration.py); yield chosen"),
      make("tomato", 0.4e6, 0.3, 1000.0, 0.1e6, 0.5, 130.0,
           "E 0.4 MPa, nu 0.3, toughness 130 J/m^2, puncture strength 100 kPa (Jamdagni & Jia, IROS "
           "2019); rho, yield and friction chosen"),
      make("banana", 0.5e6, 0.35, 950.0, 0.08e6, 0.4, 60.0,
           "chosen: E in the unverified 0.1-1 MPa range of the food-texture literature; toughness chosen"),
      make("strawberry", 0.3e6, 0.35, 900.0, 0.05e6, 0.4, 50.0,
           "chosen: E in the unverified 0.1-1 MPa range of the food-texture literature; toughness chosen"),
      make("peach", 1.5e6, 0.3, 950.0, 0.2e6, 0.5, 100.0,
           "chosen: E in the unverified 0.5-5 MPa range of the food-texture literature; toughness chosen"),
      make("melon", 2.0e6, 0.3, 930.0, 0.25e6, 0.5, 150.0,
           "chosen: E in the unverified 0.5-5 MPa range of the food-texture literature; toughness chosen"),
      make("orange", 1.0e6, 0.3, 950.0, 0.15e6, 0.5, 100.0,
           "chosen: E in the unverified 0.5-5 MPa range of the food-texture literature; toughness chosen"),
      make("generic", 0.5e6, 0.3, 1000.0, 0.0, 0.5, 100.0,
           "chosen: a soft elastic solid in the middle of the paper's 0.1-0.9 MPa sweep"),
  };
}

}  // namespace

double Material::dilatational_wave_speed_m_s() const {
  return std::sqrt((lame_lambda_pa() + 2.0 * shear_modulus_pa() + 4.0 / 3.0 * maxwell_shear_modulus_pa()) /
                   density_kg_m3);
}

void ValidateMaterial(const Material& material) {
  const std::string where = "material '" + material.name + "': ";
  // Foods are far softer than 1 GPa; stiffer asks for millions of substeps per second.
  if (!(material.youngs_modulus_pa > 0.0 && material.youngs_modulus_pa <= 1e9)) {
    throw std::invalid_argument(where + "youngs_modulus_pa must be in (0, 1e9] Pa");
  }
  if (!(material.poisson_ratio > -1.0 && material.poisson_ratio < 0.5)) {
    throw std::invalid_argument(where + "poisson_ratio must lie in (-1, 0.5)");
  }
  if (!(material.density_kg_m3 >= 10.0 && material.density_kg_m3 <= 1e4)) {
    throw std::invalid_argument(where + "density_kg_m3 must be in [10, 1e4] kg/m^3");
  }
  if (!(material.yield_stress_pa >= 0.0 && std::isfinite(material.yield_stress_pa))) {
    throw std::invalid_argument(where + "yield_stress_pa must be >= 0 (0 turns plasticity off)");
  }
  if (!(material.viscoplastic_relaxation_time_s >= 0.0 &&
        std::isfinite(material.viscoplastic_relaxation_time_s))) {
    throw std::invalid_argument(where + "viscoplastic_relaxation_time_s must be >= 0 (0: rate-independent)");
  }
  if (!(material.friction_coefficient >= 0.0 && std::isfinite(material.friction_coefficient))) {
    throw std::invalid_argument(where + "friction_coefficient must be >= 0");
  }
  if (!(material.board_friction_coefficient >= 0.0 && std::isfinite(material.board_friction_coefficient))) {
    throw std::invalid_argument(where + "board_friction_coefficient must be >= 0");
  }
  // A branch far stiffer than the base would make the food's wave speed, and so its substeps, explode.
  if (!(material.maxwell_modulus_ratio >= 0.0 && material.maxwell_modulus_ratio <= 100.0)) {
    throw std::invalid_argument(where + "maxwell_modulus_ratio must be in [0, 100] (0: no Maxwell branch)");
  }
  if (!(material.maxwell_relaxation_time_s >= 0.0 && material.maxwell_relaxation_time_s <= 1e6)) {
    throw std::invalid_argument(where + "maxwell_relaxation_time_s must be in [0, 1e6] s (0: no Maxwell branch)");
  }
  // Tough plant tissue is below 1 kJ/m^2; far above that the knife could not cut at all.
  if (!(material.fracture_toughness_j_m2 >= 0.0 && material.fracture_toughness_j_m2 <= 1e4)) {
    throw std::invalid_argument(where + "fracture_toughness_j_m2 must be in [0, 1e4] J/m^2");
  }
}

Material MaterialPreset(const std::string& name) {
  std::string names;
  for (const Material& preset : Presets()) {
    if (preset.name == name) return preset;
    names += (names.empty() ? "" : ", ") + preset.name;
  }
  throw std::invalid_argument("unknown material preset '" + name + "'; presets: " + names);
}

std::vector<std::string> MaterialPresetNames() {
  std::vector<std::string> names;
  for (const Material& preset : Presets()) names.push_back(preset.name);
  return names;
}

}  // namespace culinarycut::mpm
