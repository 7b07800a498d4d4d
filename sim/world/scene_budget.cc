#include "sim/world/scene_budget.h"

namespace culinarycut {

double EstimatedParticles(const Eigen::Vector3d& extent_m, double dx_m, int particles_per_cell) {
  return extent_m.prod() / (dx_m * dx_m * dx_m) * particles_per_cell;
}

double EstimatedGridNodes(const Eigen::AlignedBox3d& bounds_m, double dx_m) {
  constexpr double kMarginCells = 4.0;
  const Eigen::Vector3d cells = (bounds_m.sizes() / dx_m).array() + 2 * kMarginCells + 1;
  return cells.prod();
}

std::size_t EstimatedSessionBytes(std::size_t particles, double grid_nodes, std::int64_t camera_pixels) {
  return kRobotSessionBytes + particles * kBytesPerParticle +
         static_cast<std::size_t>(grid_nodes) * kBytesPerGridNode +
         static_cast<std::size_t>(camera_pixels) * kBytesPerPixel;
}

}  // namespace culinarycut
