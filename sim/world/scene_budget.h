// What a scene will cost, estimated before any work is done, and the limits one scene must keep:
// particles (from each food's box, scale and resolution, before sampling), the MPM grid at the
// start, MPM substeps per control step, camera pixels, and the memory a session will hold. A scene
// past a limit is refused at compile time naming the limit and what to lower, so no request can
// take the machine (a fine melon at scale 3 is refused in microseconds, not after 7 GB of sampling).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

namespace culinarycut {

// Largest food a session may hold; more needs a coarser quality or a smaller scale.
inline constexpr std::size_t kMaxFoodParticles = 2'000'000;
// Grid nodes of the box around all foods at the start (16 B each: 320 MB).
inline constexpr double kMaxInitialGridNodes = 2e7;
// MPM substeps in one control step (CFL factor, grid spacing and stiffness decide it).
inline constexpr double kMaxMpmSubstepsPerControlStep = 50'000;
// Pixels of all cameras of one session together (e.g. 4 cameras of 1024 x 1024).
inline constexpr std::int64_t kMaxCameraPixelsPerSession = 4'194'304;
// Memory a robot-only session holds (the Bullet world, the robot model), measured: 3,072 sessions
// took 21.9 GB.
inline constexpr std::size_t kRobotSessionBytes = 8u << 20;
inline constexpr std::size_t kBytesPerParticle = 320;  // solver arrays, blocks and scratch
inline constexpr std::size_t kBytesPerGridNode = 64;   // node momentum and mass, split nodes, growth
inline constexpr std::size_t kBytesPerPixel = 16;      // colour, depth, labels and the encoded copy

// Upper bound on the particles a food box (its local extent, m) holds at spacing dx (m).
double EstimatedParticles(const Eigen::Vector3d& extent_m, double dx_m, int particles_per_cell);

// Grid nodes of the box `bounds_m` at spacing dx, with the solver's margin on every side.
double EstimatedGridNodes(const Eigen::AlignedBox3d& bounds_m, double dx_m);

// The memory a session of this size will hold (bytes).
std::size_t EstimatedSessionBytes(std::size_t particles, double grid_nodes, std::int64_t camera_pixels);

}  // namespace culinarycut
