// Topology: which particles still hold together. Connected components over particles that are
// close (within a link distance), not broken (damage below a threshold) and not parted by a cut
// (cut_record.h), giving the pieces an object has been cut into and where the cuts lie along its
// long axis.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "sim/mpm/particles.h"

namespace culinarycut::mpm {

struct TopologyOptions {
  double link_distance_m = 0.004;   // particles closer than this are neighbours (about dx)
  double broken_damage = 0.9;       // particles with D >= this link to nobody
  int min_piece_particles = 1;      // smaller components are labelled -1 (crumbs), not pieces
  bool separate_blade_sides = true; // particles on opposite blade sides (CPIC labels) never link
  bool separate_cut_sides = true;   // particles a past cut put on opposite sides never link again
};

struct Piece {
  std::int32_t label = 0;           // 0, 1, ... ordered by the piece's lowest particle index
  std::uint16_t object = 0;         // the food object its particles came from
  std::size_t particle_count = 0;
  double volume_m3 = 0.0;           // sum of particle volumes (initial)
  double mass_kg = 0.0;
  Eigen::AlignedBox3d bounds_m;     // world-space bounding box of its particles
  Eigen::AlignedBox3d rest_bounds_m;  // the same of where its particles were sampled (material coordinates)
  Eigen::Vector3d centroid_m = Eigen::Vector3d::Zero();  // mass-weighted
};

// Labels every particle's `piece` and returns the pieces. Deterministic: same particles, same
// labels, whatever the thread count. Broken particles and crumbs get label -1.
template <typename Real>
std::vector<Piece> DetectPieces(const TopologyOptions& options, Particles<Real>* particles);

// Cut positions along an axis (from `axis_origin_m` along unit `axis_direction`, in metres) for
// the pieces of one object: one cut midway between each pair of neighbouring pieces, by the
// pieces' extents projected on the axis. Pieces of other objects are ignored.
std::vector<double> CutPositionsAlongAxis(const std::vector<Piece>& pieces, std::uint16_t object,
                                          const Eigen::Vector3d& axis_origin_m,
                                          const Eigen::Vector3d& axis_direction);

}  // namespace culinarycut::mpm
