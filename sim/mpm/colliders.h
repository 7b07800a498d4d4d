// Rigid colliders as signed distance fields (SDF) in the world frame: the knife (a thin blade with
// a bevelled edge, and a handle), the cutting board and the table. Each is moved rigidly by a pose
// and a velocity given every step; the solver queries them only inside their bounding boxes.
#pragma once

#include <Eigen/Geometry>

namespace culinarycut::mpm {

// Where a collider is and how it moves: the velocity of a point p of the body is
// linear_velocity + angular_velocity x (p - pose.translation()).
struct RigidMotion {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d linear_velocity_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_rad_s = Eigen::Vector3d::Zero();

  Eigen::Vector3d VelocityAt(const Eigen::Vector3d& point_m) const {
    return linear_velocity_m_s + angular_velocity_rad_s.cross(point_m - pose.translation());
  }
};

// One SDF query: distance (m, negative inside), outward unit normal (the SDF's gradient).
struct SdfSample {
  double distance_m = 0.0;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};

// The knife of assets/panda (docs/robot.md), in the knife TCP frame: x along the blade towards
// the tip, y the blade normal, z from the spine towards the edge; the TCP is the middle of the
// cutting edge. The blade is a plate whose lower part tapers to the edge (the bevel).
struct KnifeGeometry {
  double blade_length_m = 0.20;     // along x, centred on the TCP
  double blade_height_m = 0.045;    // spine to edge, along z
  double blade_thickness_m = 0.002; // along y, at the spine
  double bevel_height_m = 0.008;    // the bottom part that tapers to a sharp edge
  // SDF thickness is at least this many grid cells. One cell is enough with the two-sided blade and keeps the
  // cut gap near one cell; the blade's own 2 mm (0) makes the force follow dx less but does not yet always
  // separate the food at the draft grid (docs/mpm.md, "Blade thickness").
  double min_thickness_cells = 0.0;
  Eigen::Vector3d handle_size_m{0.11, 0.02, 0.025};        // box behind the heel
  Eigen::Vector3d handle_center_in_tcp_m{-0.155, 0.0, -0.03};
};

enum class KnifePart { kBlade, kHandle };

class KnifeSdf {
 public:
  // `dx_m` fixes the blade's effective SDF thickness: max(thickness, min_thickness_cells * dx).
  KnifeSdf(const KnifeGeometry& geometry, double dx_m);

  void SetMotion(const RigidMotion& tcp_motion);  // the TCP frame's pose and velocity
  const RigidMotion& motion() const { return motion_; }
  // A world point in the TCP frame: x along the blade, y its side (SideOfBlade), -z its height
  // above the edge (HeightAboveEdge). One transform for all three queries.
  Eigen::Vector3d ToTcpFrame(const Eigen::Vector3d& world_m) const { return world_to_tcp_ * world_m; }

  // Distance to one part at a world point.
  SdfSample Blade(const Eigen::Vector3d& world_m) const;
  SdfSample Handle(const Eigen::Vector3d& world_m) const;
  // Signed distance of a world point to the blade's mid-plane (y = 0 in the TCP frame), m:
  // which side of the blade a point is on.
  double SideOfBlade(const Eigen::Vector3d& world_m) const;
  // Height of a world point above the edge along the blade's z (m; > 0 is above the edge, i.e.
  // towards the spine), and whether it lies within the blade's length.
  double HeightAboveEdge(const Eigen::Vector3d& world_m) const;
  bool WithinBladeLength(const Eigen::Vector3d& world_m) const;

  // World-space boxes containing each part, padded by `margin_m`.
  Eigen::AlignedBox3d BladeBounds(double margin_m) const;
  Eigen::AlignedBox3d HandleBounds(double margin_m) const;
  // Signed distance (m) to the nearer of the boxes around the blade and the handle, in the TCP
  // frame: cheaper than the parts' SDFs and never more than either.
  double BoxDistance(const Eigen::Vector3d& world_m) const;

  const KnifeGeometry& geometry() const { return geometry_; }
  double effective_thickness_m() const { return thickness_m_; }

 private:
  // The box around the blade in the TCP frame: spine at z = 0, edge at -blade_height_m.
  Eigen::Vector3d BladeBoxCenter() const;
  Eigen::Vector3d BladeBoxHalfSize() const;

  KnifeGeometry geometry_;
  double thickness_m_;
  RigidMotion motion_;
  Eigen::Isometry3d world_to_tcp_ = Eigen::Isometry3d::Identity();  // inverse of motion_.pose
};

// A static or moving box (the cutting board), or the half-space below a plane (the table top).
class BoxSdf {
 public:
  BoxSdf(const Eigen::Vector3d& size_m, const RigidMotion& motion);
  SdfSample Sample(const Eigen::Vector3d& world_m) const;
  // Strictly inside the box: exactly where Sample's distance is negative, for a fraction of its cost.
  bool Contains(const Eigen::Vector3d& world_m) const {
    return ((world_to_local_ * world_m).cwiseAbs() - half_size_m_).maxCoeff() < 0.0;
  }
  Eigen::AlignedBox3d Bounds(double margin_m) const;
  const RigidMotion& motion() const { return motion_; }
  void SetMotion(const RigidMotion& motion) {
    motion_ = motion;
    world_to_local_ = motion.pose.inverse();
  }

 private:
  Eigen::Vector3d half_size_m_;
  RigidMotion motion_;
  // Inverse of motion_.pose, kept: the grid update samples the board at every node near it.
  Eigen::Isometry3d world_to_local_ = Eigen::Isometry3d::Identity();
};

class HalfSpaceSdf {
 public:
  // Solid below the horizontal plane z = height_m (the table); normal +z.
  explicit HalfSpaceSdf(double height_m) : height_m_(height_m) {}
  SdfSample Sample(const Eigen::Vector3d& world_m) const {
    return {world_m.z() - height_m_, Eigen::Vector3d::UnitZ()};
  }
  double height_m() const { return height_m_; }

 private:
  double height_m_;
};

}  // namespace culinarycut::mpm
