// Food geometry as signed distance fields in the food's own frame, and particle sampling from
// them. Sizes are typical for each food and multiplied by `scale`.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "sim/mpm/particles.h"

namespace culinarycut::mpm {

// A food's shape in its local frame: origin at the centre of its bounding box, the long axis
// along local x, lying on its side (local z up). Negative distance inside, metres.
class FoodShape {
 public:
  virtual ~FoodShape() = default;
  virtual double SignedDistance(const Eigen::Vector3d& local_m) const = 0;
  // Tight local bounding box (m).
  virtual Eigen::AlignedBox3d LocalBounds() const = 0;
  virtual std::string food() const = 0;
};

// banana (curved), cucumber, apple, peach, melon, orange, strawberry. `scale` > 0 multiplies
// every length of the typical size. Throws std::invalid_argument for an unknown food or scale.
std::unique_ptr<FoodShape> MakeFoodShape(const std::string& food, double scale = 1.0);
std::vector<std::string> FoodShapeNames();

// The shape's volume (m^3), by the midpoint rule on a 48^3 lattice over its bounds (about 1 % for
// the foods' smooth shapes): the shapes are unions of SDF primitives with no closed-form volume.
double EstimatedVolume(const FoodShape& shape);

struct SamplingOptions {
  double dx_m = 0.004;          // grid spacing the particles are sampled for
  int particles_per_cell = 8;   // per dx^3 cell, >= 1
  std::uint64_t seed = 0;       // jitter; same seed -> same particles
};

// Fills `particles` with jittered samples of `shape` placed at `pose` (world), each with mass
// rho * dx^3 / ppc and that volume. Returns the number added. Deterministic for a seed.
template <typename Real>
std::size_t SampleFood(const FoodShape& shape, const Eigen::Isometry3d& pose, double density_kg_m3,
                       std::uint16_t material_id, std::uint16_t object_id,
                       const SamplingOptions& options, Particles<Real>* particles);

}  // namespace culinarycut::mpm
