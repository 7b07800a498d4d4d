// Named food material presets with their sources (cited per preset in materials.cc); every value can
// be overridden. SI units throughout.
#pragma once

#include <string>
#include <vector>

namespace culinarycut::mpm {

struct Material {
  std::string name;                   // preset name, e.g. "cucumber"
  double youngs_modulus_pa = 1e6;     // E
  double poisson_ratio = 0.3;         // nu, in (-1, 0.5)
  double density_kg_m3 = 1000.0;      // rho
  double yield_stress_pa = 0.0;       // J2 yield stress sigma_y; 0 = no plasticity
  // 0: rate-independent radial return; > 0: the overstress relaxes with this time constant
  // (Perzyna-style: a fraction dt / (t + dt) of it returns each step).
  double viscoplastic_relaxation_time_s = 0.0;
  double friction_coefficient = 0.5;        // Coulomb, the knife (blade and handle) against this food
  double board_friction_coefficient = 0.5;  // Coulomb, the board and the table against this food
  // Fracture toughness G_c, J/m^2: the energy to open a unit area of cut. The knife's edge pushes
  // on the food with at most G_c per metre of edge in it (Atkins, "The Science and Engineering of
  // Cutting": F = G_c L + friction), so this, not dx, sets the edge's share of the force. 0: no edge
  // resistance (the blade's faces alone push back). The cucumber and potato presets hold an effective
  // value calibrated against LS-DYNA cutting references (docs/physics_validation.md).
  double fracture_toughness_j_m2 = 100.0;
  // Viscoelasticity (physics/viscoelasticity.h): a Maxwell branch of shear modulus maxwell_modulus_ratio
  // x mu beside the elastic base, relaxing with maxwell_relaxation_time_s (a standard linear solid). E is
  // then the equilibrium (long-time) modulus and E (1 + ratio) the instantaneous one in shear. 0: none.
  double maxwell_modulus_ratio = 0.0;
  double maxwell_relaxation_time_s = 0.0;
  std::string source;                 // where the numbers come from

  double shear_modulus_pa() const { return youngs_modulus_pa / (2.0 * (1.0 + poisson_ratio)); }
  double lame_lambda_pa() const {
    return youngs_modulus_pa * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
  }
  // The Maxwell branch's shear modulus mu_1 (Pa); 0 without a branch.
  double maxwell_shear_modulus_pa() const {
    return maxwell_modulus_ratio > 0.0 && maxwell_relaxation_time_s > 0.0
               ? maxwell_modulus_ratio * shear_modulus_pa()
               : 0.0;
  }
  // Instantaneous P-wave speed sqrt((lambda + 2 mu + 4/3 mu_1) / rho), m/s: what the CFL time step is
  // bound by (the Maxwell branch stiffens a fast load by its deviatoric 4/3 mu_1).
  double dilatational_wave_speed_m_s() const;
};

// Throws std::invalid_argument naming the field when a value is out of range.
void ValidateMaterial(const Material& material);

// The preset for a food (banana, cucumber, apple, peach, melon, orange, strawberry) or "generic".
// Throws std::invalid_argument listing the presets for an unknown name.
Material MaterialPreset(const std::string& name);
std::vector<std::string> MaterialPresetNames();

}  // namespace culinarycut::mpm
