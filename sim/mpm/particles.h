// The material points of an MLS-MPM simulation, stored as a structure of arrays so that each
// transfer streams through the fields it needs (MuJoCo-style plain data; no behaviour here).
// The solver reorders the particles now and then to keep neighbours together in memory: a
// particle's index is not stable over a simulation; its fields (object, damage, ...) travel
// with it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace culinarycut::mpm {

// Which side of the knife blade a particle is on (CPIC): set when the blade first comes near.
enum class BladeSide : std::int8_t { kUnassigned = 0, kNegative = -1, kPositive = 1 };

// Particles::activity of a frozen particle: not integrated, its stress a fixed load on the grid.
inline constexpr std::uint8_t kFrozen = 255;

// `Real` is float (speed) or double (verification); every solver is instantiated for both.
template <typename Real>
struct Particles {
  std::array<std::vector<Real>, 3> position;   // m, world frame
  std::array<std::vector<Real>, 3> velocity;   // m/s
  // Where it was sampled (m, world frame): its material coordinates, so that a cut can be placed where
  // the blade passed whatever the pieces did afterwards.
  std::array<std::vector<Real>, 3> rest_position;
  std::array<std::vector<Real>, 9> F;          // deformation gradient, row-major 3x3
  std::array<std::vector<Real>, 9> C;          // APIC/MLS affine velocity field, row-major, 1/s
  std::vector<Real> mass;                      // kg
  std::vector<Real> volume;                    // initial volume, m^3
  std::vector<Real> plastic_strain;            // accumulated equivalent plastic strain (alpha)
  // Kirchhoff stress of the material's Maxwell branch (Pa; xx yy zz xy yz zx, physics/viscoelasticity.h);
  // zero for a material without one.
  std::array<std::vector<Real>, 6> maxwell_stress;
  std::vector<Real> damage;                    // D in [0, 1]; scales the Lame parameters by 1 - D
  std::vector<std::int32_t> piece;             // connected-piece label from topology (-1: none yet)
  std::vector<std::int8_t> blade_side;         // BladeSide
  std::vector<std::uint32_t> cut_sides;        // which side of each past cut (cut_record.h)
  std::vector<std::uint16_t> material;         // index into the solver's material table
  std::vector<std::uint16_t> object;           // index of the food object it was sampled from
  // Activity (solver_config.h): consecutive quiet checks of a moving particle, or kFrozen. Frozen
  // particles are stored after all the others.
  std::vector<std::uint8_t> activity;

  std::size_t size() const { return mass.size(); }

  // Adds one particle at rest, undeformed.
  void Add(const std::array<Real, 3>& x_m, Real mass_kg, Real volume_m3, std::uint16_t material_id,
           std::uint16_t object_id) {
    for (int axis = 0; axis < 3; ++axis) {
      position[axis].push_back(x_m[axis]);
      velocity[axis].push_back(Real(0));
      rest_position[axis].push_back(x_m[axis]);
    }
    for (int k = 0; k < 9; ++k) {
      F[k].push_back(k % 4 == 0 ? Real(1) : Real(0));
      C[k].push_back(Real(0));
    }
    mass.push_back(mass_kg);
    volume.push_back(volume_m3);
    plastic_strain.push_back(Real(0));
    for (auto& component : maxwell_stress) component.push_back(Real(0));
    damage.push_back(Real(0));
    piece.push_back(-1);
    blade_side.push_back(static_cast<std::int8_t>(BladeSide::kUnassigned));
    cut_sides.push_back(0u);
    material.push_back(material_id);
    object.push_back(object_id);
    activity.push_back(0);
  }
};

}  // namespace culinarycut::mpm
