// Which food a collider touches: each material's own knife and board friction and speed resistance,
// found for a contact node from the bounding boxes of that material's particles this substep (foods
// lie apart on the board, so a node near a collider belongs to one of them).
#pragma once

#include <algorithm>
#include <limits>
#include <vector>

#include <Eigen/Geometry>

#include "sim/mpm/materials.h"
#include "sim/mpm/particles.h"
#include "sim/mpm/solver_config.h"

namespace culinarycut::mpm {

struct ContactMaterial {
  double knife_friction = 0.5;  // Coulomb, blade and handle
  double board_friction = 0.5;  // Coulomb, board and table
  double k2_per_s = 0.0;        // quadratic speed resistance of the knife in this food (1 / (m/s) / s)
  double toughness_j_m2 = 0.0;  // G_c: the most the edge pushes with, per metre of edge (N/m)
  double density_kg_m3 = 1000.0;  // inertial (times the mass scaling): how full an edge node is, mass / rho dx^3
  double wave_speed_m_s = 0.0;    // dilatational, at real mass: the speed resistance's grid speed (solver_config.h)
};

// The paper's speed-resistance constant: k2 = k2_0 (E / E_ref)(1 + sigma_y / sigma_y,ref).
inline double SpeedResistance(const Material& material, const CuttingParameters& cutting) {
  return cutting.k2_reference_per_s * (material.youngs_modulus_pa / cutting.k2_reference_youngs_pa) *
         (1.0 + material.yield_stress_pa / cutting.k2_reference_yield_pa);
}

class ContactMaterials {
 public:
  ContactMaterials() = default;
  ContactMaterials(const std::vector<Material>& materials, const CuttingParameters& cutting,
                   double mass_scaling = 1.0) {
    for (const Material& material : materials) {
      table_.push_back({material.friction_coefficient, material.board_friction_coefficient,
                        SpeedResistance(material, cutting), material.fracture_toughness_j_m2,
                        mass_scaling * material.density_kg_m3, material.dilatational_wave_speed_m_s()});
    }
    uniform_ = std::all_of(table_.begin(), table_.end(), [&](const ContactMaterial& m) {
      return m.knife_friction == table_[0].knife_friction && m.board_friction == table_[0].board_friction &&
             m.k2_per_s == table_[0].k2_per_s && m.toughness_j_m2 == table_[0].toughness_j_m2 &&
             m.density_kg_m3 == table_[0].density_kg_m3 && m.wave_speed_m_s == table_[0].wave_speed_m_s;
    });
  }

  // Every material touches the colliders alike: no lookup needed.
  bool uniform() const { return uniform_; }

  // This substep's particle bounds per material (only when they differ), grown by `margin_m`.
  template <typename Real>
  void Measure(const Particles<Real>& particles, double margin_m) {
    if (uniform_) return;
    bounds_.assign(table_.size(), Eigen::AlignedBox3d());
    for (std::size_t q = 0; q < particles.size(); ++q) {
      bounds_[particles.material[q]].extend(Eigen::Vector3d(particles.position[0][q], particles.position[1][q],
                                                            particles.position[2][q]));
    }
    for (Eigen::AlignedBox3d& box : bounds_) {
      if (!box.isEmpty()) box = Eigen::AlignedBox3d(box.min().array() - margin_m, box.max().array() + margin_m);
    }
  }

  // The material of the food at node x: the one whose box holds it, else the nearest box.
  const ContactMaterial& At(const Eigen::Vector3d& x) const {
    if (uniform_) return table_[0];
    std::size_t best = 0;
    double best_distance = std::numeric_limits<double>::infinity();
    for (std::size_t m = 0; m < bounds_.size(); ++m) {
      if (bounds_[m].isEmpty()) continue;
      const double distance = bounds_[m].exteriorDistance(x);
      if (distance < best_distance) {
        best_distance = distance;
        best = m;
      }
      if (distance == 0.0) break;
    }
    return table_[best];
  }

 private:
  std::vector<ContactMaterial> table_;
  std::vector<Eigen::AlignedBox3d> bounds_;
  bool uniform_ = true;
};

}  // namespace culinarycut::mpm
