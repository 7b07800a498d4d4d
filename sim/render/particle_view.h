// A read-only view of the food's material points, all the renderer knows of the MPM solver.
// Plain pointers into the solver's structure-of-arrays storage; valid for one render call.
#pragma once

#include <cstddef>
#include <cstdint>

namespace culinarycut::render {

struct ParticleView {
  std::size_t count = 0;
  const float* x_m = nullptr;              // positions, world frame (m)
  const float* y_m = nullptr;
  const float* z_m = nullptr;
  const float* damage = nullptr;           // D in [0, 1]; null means undamaged everywhere
  const std::int32_t* piece = nullptr;     // connected-piece label; null or negative: piece 0
  const std::uint16_t* object = nullptr;   // food object index (into RenderFood::objects); null means 0
  // Typical distance between neighbours: dx / ppc^(1/3). Each particle fills spacing^3 of food:
  // a spacing too large makes the surface too fat.
  float particle_spacing_m = 0.0f;
};

}  // namespace culinarycut::render
