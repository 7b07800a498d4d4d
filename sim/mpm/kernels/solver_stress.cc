// P2G, part 1: each particle's stress (J2 plastic return, damaged corotated) folded into its
// affine momentum matrix -dt vol 4/dx^2 tau + m C, and from it what the particle adds to its
// nodes; in storage order: independent per particle, 8 particles per SIMD batch.
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "sim/mpm/kernels/polar_batch.h"
#include "sim/mpm/kernels/solver_internals.h"
#include "sim/mpm/kernels/stress_batch.h"
#include "sim/mpm/physics/constitutive.h"
#include "sim/mpm/physics/viscoelasticity.h"

namespace culinarycut::mpm {

// Particles [begin, end), a chunk of at most kChunk (P2G's scatter takes the chunks and then the
// blocks from one queue). For the frozen load (`frozen_load`), a particle at rest has relaxed: the
// return to the yield surface is complete whatever dt, and it is not stored (the load is then a
// function of the frozen particles alone, the same whenever it is rebuilt).
template <typename Real>
double Solver<Real>::ComputeAffineMomentum(const SubstepContext& context, std::size_t begin,
                                           std::size_t end, bool frozen_load) {
  Particles<Real>& p = particles_;
  Workspace& work = *workspace_;
  const Effects& effects = config().effects;
  const double dt_s = context.dt_s;
  const Real dt = Real(dt_s);
  const Real dx = Real(context.dx_m);
  const Real inv_dx = Real(1.0 / context.dx_m);
  const Real stress_scale = -dt * Real(4) * inv_dx * inv_dx;
  // What particles q .. q + W - 1 add to their nodes, from their affine momentum matrices in lanes.
  auto transfer_values = [&](std::size_t q, const auto& affine) {
    constexpr int kWidth = std::extent_v<std::remove_reference_t<decltype(affine)>, 1>;
    Real mass[kWidth], velocity[3][kWidth], position[3][kWidth];
    for (int l = 0; l < kWidth; ++l) {
      mass[l] = p.mass[q + l];
      for (int axis = 0; axis < 3; ++axis) {
        velocity[axis][l] = p.velocity[axis][q + l];
        position[axis][l] = p.position[axis][q + l];
      }
    }
    NodeMomentumBatch<Real, kWidth>(affine, mass, velocity, position, inv_dx, dx,
                                    &work.node_momentum[q]);
  };
  // J2 radial return of particle q (F updated in place and stored); false when it did not flow.
  auto plastic_return = [&](std::size_t q, const Matrix3<Real>& R, Matrix3<Real>* F) {
    const Material& material = materials()[p.material[q]];
    if (!effects.plasticity || material.yield_stress_pa <= 0.0) return false;
    const Real fraction = material.viscoplastic_relaxation_time_s > 0.0 && !frozen_load
                              ? Real(dt_s / (material.viscoplastic_relaxation_time_s + dt_s))
                              : Real(1);
    const Real plastic = ReturnToYieldSurface(F, R, Real(material.yield_stress_pa),
                                              Real(material.shear_modulus_pa()), fraction);
    if (plastic <= Real(0)) return false;
    if (frozen_load) return true;
    p.plastic_strain[q] += plastic;
    for (int k = 0; k < 9; ++k) p.F[k][q] = (*F)(k / 3, k % 3);
    return true;
  };
  // Adds particle q's Maxwell branch stress, softened by its damage like the shear it is, to its
  // Kirchhoff stress; returns the energy density the branch stores (J/m^3).
  auto add_maxwell_stress = [&](std::size_t q, Matrix3<Real>* tau) {
    const Real mu_1 = Real(materials()[p.material[q]].maxwell_shear_modulus_pa());
    if (!(mu_1 > Real(0))) return Real(0);
    Real branch[6];
    for (int k = 0; k < 6; ++k) branch[k] = p.maxwell_stress[k][q];
    const Real intact = Real(1) - p.damage[q];
    for (int k = 0; k < 6; ++k) {
      (*tau)(kSymmetricRow[k], kSymmetricColumn[k]) += intact * branch[k];
      if (k >= kXY) (*tau)(kSymmetricColumn[k], kSymmetricRow[k]) += intact * branch[k];
    }
    return intact * MaxwellEnergyDensity(branch, mu_1);
  };
  // Stress of one particle given its rotation R; returns its elastic energy (J).
  auto particle_stress = [&](std::size_t q, const Matrix3<Real>& R) {
    Matrix3<Real> F;
    for (int k = 0; k < 9; ++k) F(k / 3, k % 3) = p.F[k][q];
    const Material& material = materials()[p.material[q]];
    plastic_return(q, R, &F);
    const Real J = F.determinant();
    const Lame<Real> lame = DamagedLame(Real(material.shear_modulus_pa()), Real(material.lame_lambda_pa()),
                                        p.damage[q], J);
    Matrix3<Real> tau = CorotatedKirchhoffStress(F, R, J, lame);
    const Real volume_scale = stress_scale * p.volume[q];
    const Real m = p.mass[q];
    const Real maxwell_energy = add_maxwell_stress(q, &tau);
    Real affine[9][1];
    for (int k = 0; k < 9; ++k) affine[k][0] = volume_scale * tau(k / 3, k % 3) + m * p.C[k][q];
    transfer_values(q, affine);
    return double(p.volume[q]) * (CorotatedEnergyDensity(F, R, J, lame) + maxwell_energy);
  };
  // Per-material constants, computed once per substep rather than per particle.
  struct MaterialConstants {
    Real mu;                    // Pa
    Real lambda;                // Pa
    Real yield_test_strain_sq;  // plastic flow is possible above ~0.7 of the yield strain
  };
  // A few materials at most: on the stack, no allocation per chunk.
  constexpr std::size_t kStackMaterials = 8;
  MaterialConstants stack_constants[kStackMaterials];
  std::vector<MaterialConstants> heap_constants;
  if (materials().size() > kStackMaterials) heap_constants.resize(materials().size());
  MaterialConstants* const material_constants =
      materials().size() > kStackMaterials ? heap_constants.data() : stack_constants;
  bool any_plastic = false;
  bool any_maxwell = false;  // off: the branch's arrays are not read
  for (std::size_t m = 0; m < materials().size(); ++m) {
    const Material& material = materials()[m];
    any_maxwell = any_maxwell || material.maxwell_shear_modulus_pa() > 0.0;
    // The same early-out as ReturnToYieldSurface (see YieldTestFraction).
    const double full_yield_strain =
        std::sqrt(2.0 / 3.0) * material.yield_stress_pa / (2.0 * material.shear_modulus_pa());
    const double yield_strain = effects.plasticity && material.yield_stress_pa > 0.0
                                    ? YieldTestFraction(full_yield_strain) * full_yield_strain
                                    : 1e15;
    any_plastic = any_plastic || yield_strain < 1e15;
    material_constants[m] = {Real(material.shear_modulus_pa()), Real(material.lame_lambda_pa()),
                             Real(yield_strain * yield_strain)};
  }
  constexpr int kLanes = 8;  // particles whose polar rotations are computed together (SIMD)
  {
    double chunk_energy = 0.0;
    const std::size_t end_q = end;
    std::size_t q = begin;
    for (; q + kLanes <= end_q; q += kLanes) {
      Real F_lanes[9][kLanes], R_lanes[9][kLanes], C_lanes[9][kLanes], affine_lanes[9][kLanes];
      Real mu[kLanes], lambda[kLanes], lambda_undamaged[kLanes], volume_scale[kLanes], mass[kLanes],
          volume[kLanes];
      Real yield_strain_sq[kLanes], green_sq[kLanes], energy[kLanes];
      for (int k = 0; k < 9; ++k) {
        __builtin_prefetch(p.F[k].data() + q + kPrefetchAhead);
        __builtin_prefetch(p.C[k].data() + q + kPrefetchAhead);
      }
      for (int k = 0; k < 9; ++k) {
        for (int l = 0; l < kLanes; ++l) {
          F_lanes[k][l] = p.F[k][q + l];
          C_lanes[k][l] = p.C[k][q + l];
        }
      }
      for (int l = 0; l < kLanes; ++l) {
        const MaterialConstants& material = material_constants[p.material[q + l]];
        const Real damage_scale = Real(1) - p.damage[q + l];
        mu[l] = material.mu * damage_scale;
        lambda[l] = material.lambda * damage_scale;
        lambda_undamaged[l] = material.lambda;
        volume[l] = p.volume[q + l];
        volume_scale[l] = stress_scale * volume[l];
        mass[l] = p.mass[q + l];
        yield_strain_sq[l] = material.yield_test_strain_sq;
      }
      PolarRotationBatch<Real, kLanes>(F_lanes, R_lanes);
      if (any_plastic) DeviatoricGreenStrainSquared<Real, kLanes>(F_lanes, green_sq);
      for (int l = 0; l < kLanes && any_plastic; ++l) {
        if (green_sq[l] < yield_strain_sq[l]) continue;
        // Rare: this particle may have yielded; return it to the yield surface one at a time.
        Matrix3<Real> F, R;
        for (int k = 0; k < 9; ++k) {
          F(k / 3, k % 3) = F_lanes[k][l];
          R(k / 3, k % 3) = R_lanes[k][l];
        }
        if (plastic_return(q + l, R, &F)) {
          for (int k = 0; k < 9; ++k) F_lanes[k][l] = F(k / 3, k % 3);
        }
      }
      CorotatedAffineBatch<Real, kLanes>(F_lanes, R_lanes, C_lanes, mu, lambda, lambda_undamaged, volume_scale, mass,
                                         volume, affine_lanes, energy);
      for (int l = 0; l < kLanes && any_maxwell; ++l) {
        Matrix3<Real> branch = Matrix3<Real>::Zero();
        const Real branch_energy = add_maxwell_stress(q + l, &branch);
        for (int k = 0; k < 9; ++k) affine_lanes[k][l] += volume_scale[l] * branch(k / 3, k % 3);
        energy[l] += volume[l] * branch_energy;
      }
      transfer_values(q, affine_lanes);
      for (int l = 0; l < kLanes; ++l) chunk_energy += energy[l];
    }
    for (; q < end_q; ++q) {
      Matrix3<Real> F;
      for (int k = 0; k < 9; ++k) F(k / 3, k % 3) = p.F[k][q];
      chunk_energy += particle_stress(q, PolarRotation(F));
    }
    return chunk_energy;
  }
}

template double Solver<float>::ComputeAffineMomentum(const SubstepContext&, std::size_t, std::size_t, bool);
template double Solver<double>::ComputeAffineMomentum(const SubstepContext&, std::size_t, std::size_t, bool);

}  // namespace culinarycut::mpm
