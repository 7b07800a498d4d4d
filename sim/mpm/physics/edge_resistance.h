// The knife's edge against the food: it pushes the food ahead of it like any collider until the push
// reaches the food's toughness, and from then on the food parts around it. Cutting mechanics gives
// the edge's share of the cutting force as F = G_c L (Atkins, "The Science and Engineering of
// Cutting", 2009: the work to cut a unit area is the fracture toughness G_c, J/m^2); the faces add
// friction and the wedge. Capping each edge node's impulse at its share of G_c L dt makes the edge
// force a material property instead of the stiffness of one grid cell (which falls with dx).
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace culinarycut::mpm {

// Nodes this close to the edge line across the blade (in dx) carry the edge (EdgeAcrossWeight); along
// the cutting direction the reach is one cell (EdgeShare).
constexpr double kEdgeReachCells = 1.5;

// The weight across the blade of a node `cells` from the edge line (in dx): the quadratic B-spline,
// which sums to 1 over the nodes of any column and stays within 2.1 % of that per unit of edge length
// at every angle the edge makes with the grid (a tent of half-width 1 cell: -9 % to +12 % at 45 deg).
inline double EdgeAcrossWeight(double cells) {
  const double d = std::abs(cells);
  if (d < 0.5) return 0.75 - d * d;
  if (d < 1.5) return 0.5 * (1.5 - d) * (1.5 - d);
  return 0.0;
}

// A node's share of the edge, in [0, 1], from its offsets to the edge line: `side_m` across the
// blade and `height_m` above the edge (negative: ahead of the edge, in the food still to cut).
// `above_is_split`: whether the node a cell above this one is split by blade side (it then sees
// the blade's faces, not the edge), so this node carries the whole column's share.
inline double EdgeShare(double side_m, double height_m, double dx_m, bool above_is_split) {
  const double across = EdgeAcrossWeight(side_m / dx_m);
  if (across <= 0.0 || height_m < -dx_m || height_m >= dx_m) return 0.0;
  double along = 0.0;
  if (height_m >= 0.0) {
    along = 1.0 - height_m / dx_m;
  } else {
    along = above_is_split ? 1.0 : 1.0 + height_m / dx_m;
  }
  return across * along;
}

// How full of food a node is, in [0, 1]: its mass over that of a cell of the food.
inline double EdgeFill(double node_mass_kg, double density_kg_m3, double dx_m) {
  return std::min(1.0, node_mass_kg / (density_kg_m3 * dx_m * dx_m * dx_m));
}

// The most impulse (N s) the edge may give a node in one substep: its share of G_c times the edge
// length the node stands for (dx, scaled by how full of food the node is: EdgeFill) times dt.
inline double EdgeImpulseCap(double share, double toughness_j_m2, double fill, double dx_m, double dt_s) {
  return share * toughness_j_m2 * dx_m * fill * dt_s;
}

// Scales the velocity change `after - before` of a node of mass `mass_kg` down so that its
// impulse is at most `cap_n_s`. Returns whether it was capped (the edge then cuts into the node).
inline bool CapImpulse(const Eigen::Vector3d& before, double mass_kg, double cap_n_s, Eigen::Vector3d* after) {
  const double impulse_n_s = mass_kg * (*after - before).norm();
  if (impulse_n_s <= cap_n_s) return false;
  *after = before + (*after - before) * (cap_n_s / impulse_n_s);
  return true;
}

}  // namespace culinarycut::mpm
