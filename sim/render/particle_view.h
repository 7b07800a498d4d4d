// A read-only view of the food's material points, all the renderer knows of the MPM solver.
// Plain pointers into the solver's structure-of-arrays storage; valid for one render call.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace culinarycut::render {

struct ParticleView {
  std::size_t count = 0;
  const float* x_m = nullptr;              // positions, world frame (m)
  const float* y_m = nullptr;
  const float* z_m = nullptr;
  const float* damage = nullptr;           // D in [0, 1]; null means undamaged everywhere
  const std::int32_t* piece = nullptr;     // connected-piece label; null or negative: piece 0
  const std::uint16_t* object = nullptr;   // food object index (into RenderScene::food_names); null means 0
  // Typical distance between neighbours: dx / ppc^(1/3). Each particle fills spacing^3 of food:
  // a spacing too large makes the surface too fat.
  float particle_spacing_m = 0.0f;
};

// Particle fields owned in the same layout, for food that does not come from a solver (tests,
// benchmarks, tools), and the view of them.
struct ParticleArrays {
  std::vector<float> x, y, z, damage;  // m, m, m, [0, 1]
  std::vector<std::int32_t> piece;
  std::vector<std::uint16_t> object;
  float spacing_m = 0.0f;

  ParticleView View() const {
    ParticleView view;
    view.count = x.size();
    view.x_m = x.data();
    view.y_m = y.data();
    view.z_m = z.data();
    view.damage = damage.data();
    view.piece = piece.data();
    view.object = object.data();
    view.particle_spacing_m = spacing_m;
    return view;
  }
};

}  // namespace culinarycut::render
