#include "sim/mpm/colliders.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace culinarycut::mpm {
namespace {

// The edge keeps this fraction of the blade's half-thickness: a non-degenerate polygon, and an
// edge no thinner than a tenth of the (grid-limited) SDF thickness.
constexpr double kEdgeHalfThicknessFraction = 0.1;

// The blade's cross-section in the TCP frame's (y, z) plane: a convex hexagon, counter-clockwise
// with y to the right and z up, i.e. spine (z = -H) first, then the flank, bevel and edge (z = 0).
struct BladeProfile {
  std::array<Eigen::Vector2d, 6> vertices;
};

BladeProfile MakeBladeProfile(const KnifeGeometry& geometry, double thickness_m) {
  const double half_m = 0.5 * thickness_m;
  const double edge_half_m = kEdgeHalfThicknessFraction * half_m;
  const double height_m = geometry.blade_height_m;
  const double bevel_m = std::clamp(geometry.bevel_height_m, 0.0, height_m);
  BladeProfile profile;
  profile.vertices = {Eigen::Vector2d(-half_m, -height_m), Eigen::Vector2d(half_m, -height_m),
                      Eigen::Vector2d(half_m, -bevel_m),   Eigen::Vector2d(edge_half_m, 0.0),
                      Eigen::Vector2d(-edge_half_m, 0.0),  Eigen::Vector2d(-half_m, -bevel_m)};
  return profile;
}

// Exact signed distance to a convex counter-clockwise polygon, with its gradient. Zero-length
// edges (no bevel) are skipped.
struct Sample2d {
  double distance_m;
  Eigen::Vector2d gradient;
};

Sample2d ConvexPolygonSdf(const BladeProfile& profile, const Eigen::Vector2d& p) {
  const auto& v = profile.vertices;
  const int n = static_cast<int>(v.size());
  double best_sq = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_closest = v[0];
  Eigen::Vector2d best_edge_normal(0.0, -1.0);
  bool inside = true;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d a = v[i];
    const Eigen::Vector2d edge = v[(i + 1) % n] - a;
    const double edge_sq = edge.squaredNorm();
    if (edge_sq <= 0.0) continue;
    const Eigen::Vector2d ap = p - a;
    // Left of every CCW edge is inside.
    if (edge.x() * ap.y() - edge.y() * ap.x() < 0.0) inside = false;
    const double s = std::clamp(ap.dot(edge) / edge_sq, 0.0, 1.0);
    const Eigen::Vector2d closest = a + s * edge;
    const double dist_sq = (p - closest).squaredNorm();
    if (dist_sq < best_sq) {
      best_sq = dist_sq;
      best_closest = closest;
      best_edge_normal = Eigen::Vector2d(edge.y(), -edge.x()) / std::sqrt(edge_sq);
    }
  }
  const double dist_m = std::sqrt(best_sq);
  const double sign = inside ? -1.0 : 1.0;
  // The gradient points away from the nearest boundary point outside and towards it inside.
  Eigen::Vector2d gradient =
      dist_m > 0.0 ? Eigen::Vector2d(sign * (p - best_closest) / dist_m) : best_edge_normal;
  return {sign * dist_m, gradient};
}

// Exact box SDF in the box's own frame (centred at the origin), with its gradient.
SdfSample LocalBoxSdf(const Eigen::Vector3d& p, const Eigen::Vector3d& half_size_m) {
  const Eigen::Vector3d sign = p.unaryExpr([](double c) { return c < 0.0 ? -1.0 : 1.0; });
  const Eigen::Vector3d q = p.cwiseAbs() - half_size_m;
  const Eigen::Vector3d outside = q.cwiseMax(0.0);
  const double outside_m = outside.norm();
  SdfSample sample;
  if (outside_m > 0.0) {
    sample.distance_m = outside_m;
    sample.normal = sign.cwiseProduct(outside) / outside_m;
  } else {
    int axis = 0;
    sample.distance_m = q.maxCoeff(&axis);
    sample.normal = Eigen::Vector3d::Zero();
    sample.normal[axis] = sign[axis];
  }
  return sample;
}

Eigen::AlignedBox3d TransformedBoxBounds(const Eigen::Isometry3d& pose,
                                         const Eigen::Vector3d& center_m,
                                         const Eigen::Vector3d& half_size_m, double margin_m) {
  Eigen::AlignedBox3d bounds;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d offset((corner & 1) ? half_size_m.x() : -half_size_m.x(),
                                 (corner & 2) ? half_size_m.y() : -half_size_m.y(),
                                 (corner & 4) ? half_size_m.z() : -half_size_m.z());
    bounds.extend(pose * (center_m + offset));
  }
  const Eigen::Vector3d pad = Eigen::Vector3d::Constant(margin_m);
  return Eigen::AlignedBox3d(bounds.min() - pad, bounds.max() + pad);
}

void RequirePositive(double value, const char* name) {
  if (!(value > 0.0)) {
    throw std::invalid_argument(std::string("colliders: ") + name + " must be positive");
  }
}

}  // namespace

KnifeSdf::KnifeSdf(const KnifeGeometry& geometry, double dx_m) : geometry_(geometry) {
  RequirePositive(dx_m, "dx_m");
  RequirePositive(geometry.blade_length_m, "blade_length_m");
  RequirePositive(geometry.blade_height_m, "blade_height_m");
  RequirePositive(geometry.blade_thickness_m, "blade_thickness_m");
  RequirePositive(geometry.handle_size_m.minCoeff(), "handle_size_m");
  if (geometry.bevel_height_m < 0.0 || geometry.min_thickness_cells < 0.0) {
    throw std::invalid_argument("colliders: bevel_height_m and min_thickness_cells must be >= 0");
  }
  thickness_m_ = std::max(geometry.blade_thickness_m, geometry.min_thickness_cells * dx_m);
}

void KnifeSdf::SetMotion(const RigidMotion& tcp_motion) {
  motion_ = tcp_motion;
  world_to_tcp_ = tcp_motion.pose.inverse();
}

SdfSample KnifeSdf::Blade(const Eigen::Vector3d& world_m) const {
  const Eigen::Vector3d p = world_to_tcp_ * world_m;
  const Sample2d section =
      ConvexPolygonSdf(MakeBladeProfile(geometry_, thickness_m_), Eigen::Vector2d(p.y(), p.z()));
  // Extrude the profile along x with flat ends: exact outside, exact inside (convex profile).
  const double along_m = std::abs(p.x()) - 0.5 * geometry_.blade_length_m;
  const double x_sign = p.x() < 0.0 ? -1.0 : 1.0;
  Eigen::Vector3d local_normal;
  SdfSample sample;
  if (section.distance_m > 0.0 && along_m > 0.0) {
    sample.distance_m = std::hypot(section.distance_m, along_m);
    local_normal = Eigen::Vector3d(x_sign * along_m, section.gradient.x() * section.distance_m,
                                   section.gradient.y() * section.distance_m) /
                   sample.distance_m;
  } else if (section.distance_m >= along_m) {
    sample.distance_m = section.distance_m;
    local_normal = Eigen::Vector3d(0.0, section.gradient.x(), section.gradient.y());
  } else {
    sample.distance_m = along_m;
    local_normal = Eigen::Vector3d(x_sign, 0.0, 0.0);
  }
  sample.normal = motion_.pose.linear() * local_normal;
  return sample;
}

SdfSample KnifeSdf::Handle(const Eigen::Vector3d& world_m) const {
  const Eigen::Vector3d p = world_to_tcp_ * world_m - geometry_.handle_center_in_tcp_m;
  SdfSample sample = LocalBoxSdf(p, 0.5 * geometry_.handle_size_m);
  sample.normal = motion_.pose.linear() * sample.normal;
  return sample;
}

double KnifeSdf::SideOfBlade(const Eigen::Vector3d& world_m) const {
  return (world_to_tcp_ * world_m).y();
}

double KnifeSdf::HeightAboveEdge(const Eigen::Vector3d& world_m) const {
  // z runs from the spine down to the edge, so height above the edge is -z.
  return -(world_to_tcp_ * world_m).z();
}

bool KnifeSdf::WithinBladeLength(const Eigen::Vector3d& world_m) const {
  return std::abs((world_to_tcp_ * world_m).x()) <= 0.5 * geometry_.blade_length_m;
}

Eigen::Vector3d KnifeSdf::BladeBoxCenter() const { return Eigen::Vector3d(0.0, 0.0, -0.5 * geometry_.blade_height_m); }

Eigen::Vector3d KnifeSdf::BladeBoxHalfSize() const {
  return Eigen::Vector3d(0.5 * geometry_.blade_length_m, 0.5 * thickness_m_, 0.5 * geometry_.blade_height_m);
}

Eigen::AlignedBox3d KnifeSdf::BladeBounds(double margin_m) const {
  return TransformedBoxBounds(motion_.pose, BladeBoxCenter(), BladeBoxHalfSize(), margin_m);
}

double KnifeSdf::BoxDistance(const Eigen::Vector3d& world_m) const {
  const Eigen::Vector3d p = world_to_tcp_ * world_m;
  const double blade_m = LocalBoxSdf(p - BladeBoxCenter(), BladeBoxHalfSize()).distance_m;
  const double handle_m =
      LocalBoxSdf(p - geometry_.handle_center_in_tcp_m, 0.5 * geometry_.handle_size_m).distance_m;
  return std::min(blade_m, handle_m);
}

Eigen::AlignedBox3d KnifeSdf::HandleBounds(double margin_m) const {
  return TransformedBoxBounds(motion_.pose, geometry_.handle_center_in_tcp_m,
                              0.5 * geometry_.handle_size_m, margin_m);
}

BoxSdf::BoxSdf(const Eigen::Vector3d& size_m, const RigidMotion& motion)
    : half_size_m_(0.5 * size_m), motion_(motion), world_to_local_(motion.pose.inverse()) {
  RequirePositive(size_m.minCoeff(), "box size_m");
}

SdfSample BoxSdf::Sample(const Eigen::Vector3d& world_m) const {
  SdfSample sample = LocalBoxSdf(world_to_local_ * world_m, half_size_m_);
  sample.normal = motion_.pose.linear() * sample.normal;
  return sample;
}

Eigen::AlignedBox3d BoxSdf::Bounds(double margin_m) const {
  return TransformedBoxBounds(motion_.pose, Eigen::Vector3d::Zero(), half_size_m_, margin_m);
}

}  // namespace culinarycut::mpm
