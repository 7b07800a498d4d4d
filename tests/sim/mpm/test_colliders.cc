#include "sim/mpm/colliders.h"

#include <cmath>
#include <random>

#include <catch2/catch.hpp>

namespace culinarycut::mpm {
namespace {

constexpr double kDx = 1e-3;  // fine enough that the real 2 mm blade thickness is kept

KnifeSdf DefaultKnife(double dx_m = kDx) { return KnifeSdf(KnifeGeometry{}, dx_m); }

Eigen::Isometry3d SomePose() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()) *
                   Eigen::AngleAxisd(2.1, Eigen::Vector3d::UnitZ()))
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.3, -0.2, 0.45);
  return pose;
}

Eigen::Vector3d FiniteDifferenceGradient(const KnifeSdf& knife, const Eigen::Vector3d& p) {
  const double h = 1e-6;
  Eigen::Vector3d gradient;
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(axis);
    gradient[axis] =
        (knife.Blade(p + step).distance_m - knife.Blade(p - step).distance_m) / (2 * h);
  }
  return gradient;
}

TEST_CASE("blade distance at known points", "[mpm][colliders]") {
  const KnifeSdf knife = DefaultKnife();
  const double half_m = 0.5 * knife.effective_thickness_m();
  REQUIRE(half_m == Approx(0.001));
  // Beside the flat part (above the bevel): |y| - t/2, normal along +-y.
  SdfSample s = knife.Blade({0.03, 0.01, -0.02});
  CHECK(s.distance_m == Approx(0.01 - half_m));
  CHECK(s.normal.isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  s = knife.Blade({-0.05, -0.004, -0.03});
  CHECK(s.distance_m == Approx(0.004 - half_m));
  CHECK(s.normal.isApprox(-Eigen::Vector3d::UnitY(), 1e-12));
  // Below the edge (z > 0): the distance to the edge line, normal +z.
  s = knife.Blade({0.02, 0.0, 0.005});
  CHECK(s.distance_m == Approx(0.005));
  CHECK(s.normal.isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  // Above the spine (z < -H).
  s = knife.Blade({0.0, 0.0, -0.045 - 0.003});
  CHECK(s.distance_m == Approx(0.003));
  CHECK(s.normal.isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
  // Beyond the tip, and beyond the tip and beside the blade (the extruded corner).
  s = knife.Blade({0.1 + 0.01, 0.0, -0.02});
  CHECK(s.distance_m == Approx(0.01));
  CHECK(s.normal.isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  s = knife.Blade({0.1 + 0.003, half_m + 0.004, -0.02});
  CHECK(s.distance_m == Approx(0.005));
  CHECK(s.normal.isApprox(Eigen::Vector3d(0.6, 0.8, 0.0), 1e-12));
  // Inside: negative, the nearest face is the flank.
  s = knife.Blade({0.0, 0.0004, -0.02});
  CHECK(s.distance_m == Approx(-(half_m - 0.0004)));
  CHECK(s.normal.isApprox(Eigen::Vector3d::UnitY(), 1e-12));
  // On the surface: zero.
  CHECK(knife.Blade({0.0, half_m, -0.02}).distance_m == Approx(0.0).margin(1e-15));
}

TEST_CASE("the bevel narrows the blade towards the edge", "[mpm][colliders]") {
  const KnifeGeometry geometry;
  const KnifeSdf knife(geometry, kDx);
  const double half_m = 0.5 * knife.effective_thickness_m();
  const double edge_half_m = 0.1 * half_m;
  // The surface sits at the linearly tapering half-thickness t(z).
  for (double z : {-geometry.bevel_height_m, -0.006, -0.004, -0.002, -0.0005}) {
    const double t = edge_half_m + (half_m - edge_half_m) * (-z / geometry.bevel_height_m);
    INFO("z = " << z);
    CHECK(knife.Blade({0.0, t, z}).distance_m == Approx(0.0).margin(1e-12));
    CHECK(knife.Blade({0.0, t + 1e-5, z}).distance_m > 0.0);
    CHECK(knife.Blade({0.0, t - 1e-5, z}).distance_m < 0.0);
  }
  // At a fixed offset from the mid-plane, points nearer the edge are further from the blade.
  double previous_m = -1.0;
  for (double z : {-0.02, -0.006, -0.004, -0.002, 0.0}) {
    const double d = knife.Blade({0.0, 0.002, z}).distance_m;
    CHECK(d >= previous_m);
    previous_m = d;
  }
  CHECK(knife.Blade({0.0, 0.002, 0.0}).distance_m > knife.Blade({0.0, 0.002, -0.02}).distance_m);
  // The bevel's normal tilts towards the edge (+z) and keeps its side (+y).
  const Eigen::Vector3d n = knife.Blade({0.0, 0.003, -0.004}).normal;
  CHECK(n.y() > 0.9);
  CHECK(n.z() > 0.0);
}

TEST_CASE("no bevel and an all-bevel blade are valid profiles", "[mpm][colliders]") {
  KnifeGeometry geometry;
  geometry.bevel_height_m = 0.0;  // a plain plate: full thickness down to the edge
  const KnifeSdf plate(geometry, kDx);
  CHECK(plate.Blade({0.0, 0.003, -0.0001}).distance_m == Approx(0.002));
  CHECK(plate.Blade({0.0, 0.0, 0.002}).distance_m == Approx(0.002));
  geometry.bevel_height_m = geometry.blade_height_m;  // a wedge from the spine to the edge
  const KnifeSdf wedge(geometry, kDx);
  CHECK(wedge.Blade({0.0, 0.001, -0.045}).distance_m == Approx(0.0).margin(1e-12));
  CHECK(wedge.Blade({0.0, 0.0, -0.02}).distance_m < 0.0);
  CHECK(wedge.Blade({0.0, 0.001, -0.02}).distance_m > 0.0);
}

TEST_CASE("thin blades are thickened to min_thickness_cells * dx", "[mpm][colliders]") {
  KnifeGeometry geometry;
  CHECK(KnifeSdf(geometry, 1e-3).effective_thickness_m() == Approx(0.002));
  geometry.min_thickness_cells = 1.5;
  CHECK(KnifeSdf(geometry, 4e-3).effective_thickness_m() == Approx(1.5 * 4e-3));
  geometry.min_thickness_cells = 2.0;
  const KnifeSdf coarse(geometry, 5e-3);
  CHECK(coarse.effective_thickness_m() == Approx(0.01));
  CHECK(coarse.Blade({0.0, 0.02, -0.02}).distance_m == Approx(0.02 - 0.005));
  CHECK_THROWS(KnifeSdf(geometry, 0.0));
}

TEST_CASE("the blade SDF has unit gradient and outward normals", "[mpm][colliders]") {
  KnifeSdf knife = DefaultKnife();
  knife.SetMotion({SomePose(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(-0.13, 0.13), y(-0.02, 0.02), z(-0.07, 0.02);
  int checked = 0;
  for (int i = 0; i < 2000 && checked < 300; ++i) {
    const Eigen::Vector3d p = knife.motion().pose * Eigen::Vector3d(x(rng), y(rng), z(rng));
    const SdfSample s = knife.Blade(p);
    // Outside a convex body the distance is smooth; stay off the surface.
    if (s.distance_m < 1e-4) continue;
    ++checked;
    const Eigen::Vector3d gradient = FiniteDifferenceGradient(knife, p);
    INFO("p = " << p.transpose());
    CHECK(gradient.norm() == Approx(1.0).margin(1e-5));
    CHECK((gradient - s.normal).norm() < 1e-5);
    CHECK(s.normal.norm() == Approx(1.0));
    // Stepping back along the normal by the distance lands on the surface.
    CHECK(knife.Blade(p - s.distance_m * s.normal).distance_m == Approx(0.0).margin(1e-12));
  }
  CHECK(checked >= 300);
  // Inside, away from the mid-plane (the medial axis), too.
  const Eigen::Vector3d inside = knife.motion().pose * Eigen::Vector3d(0.01, -0.0006, -0.03);
  CHECK(FiniteDifferenceGradient(knife, inside).norm() == Approx(1.0).margin(1e-5));
  CHECK(knife.Blade(inside).normal.isApprox(
      knife.motion().pose.linear() * -Eigen::Vector3d::UnitY(), 1e-9));
}

TEST_CASE("the knife SDF moves with the TCP pose", "[mpm][colliders]") {
  const KnifeSdf at_origin = DefaultKnife();
  KnifeSdf moved = DefaultKnife();
  const Eigen::Isometry3d pose = SomePose();
  moved.SetMotion({pose, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d local(u(rng), 0.1 * u(rng), 0.3 * u(rng) - 0.02);
    const Eigen::Vector3d world = pose * local;
    const SdfSample a = at_origin.Blade(local), b = moved.Blade(world);
    CHECK(b.distance_m == Approx(a.distance_m).margin(1e-12));
    CHECK((b.normal - pose.linear() * a.normal).norm() < 1e-9);
    const SdfSample ha = at_origin.Handle(local), hb = moved.Handle(world);
    CHECK(hb.distance_m == Approx(ha.distance_m).margin(1e-12));
    CHECK((hb.normal - pose.linear() * ha.normal).norm() < 1e-9);
    CHECK(moved.SideOfBlade(world) == Approx(local.y()).margin(1e-12));
    CHECK(moved.HeightAboveEdge(world) == Approx(-local.z()).margin(1e-12));
    CHECK(moved.WithinBladeLength(world) == (std::abs(local.x()) <= 0.1));
  }
}

TEST_CASE("side of blade, height above the edge and blade length", "[mpm][colliders]") {
  KnifeSdf knife = DefaultKnife();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  // Edge pointing down (world -z), blade normal along world +x, tip along world +y.
  pose.linear() << 0, 1, 0,  //
      1, 0, 0,               //
      0, 0, -1;
  pose.translation() = Eigen::Vector3d(0.1, 0.2, 0.05);
  knife.SetMotion({pose, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
  CHECK(knife.SideOfBlade({0.13, 0.2, 0.05}) == Approx(0.03));
  CHECK(knife.SideOfBlade({0.08, 0.2, 0.05}) == Approx(-0.02));
  CHECK(knife.HeightAboveEdge({0.1, 0.2, 0.07}) == Approx(0.02));
  CHECK(knife.HeightAboveEdge({0.1, 0.2, 0.04}) == Approx(-0.01));
  CHECK(knife.WithinBladeLength({0.1, 0.29, 0.05}));
  CHECK_FALSE(knife.WithinBladeLength({0.1, 0.31, 0.05}));
  // Directly below the edge in the world is +z in the TCP frame: outside, normal world -z.
  const SdfSample below = knife.Blade({0.1, 0.2, 0.04});
  CHECK(below.distance_m == Approx(0.01));
  CHECK(below.normal.isApprox(-Eigen::Vector3d::UnitZ(), 1e-12));
}

TEST_CASE("knife bounds contain the parts and are tight", "[mpm][colliders]") {
  const KnifeGeometry geometry;
  KnifeSdf knife = DefaultKnife();
  const double margin_m = 0.002;
  // At the identity pose the boxes are the parts' own boxes, padded.
  Eigen::AlignedBox3d blade = knife.BladeBounds(margin_m);
  CHECK(blade.min().isApprox(Eigen::Vector3d(-0.1 - margin_m, -0.001 - margin_m, -0.045 - margin_m),
                             1e-12));
  CHECK(blade.max().isApprox(Eigen::Vector3d(0.1 + margin_m, 0.001 + margin_m, margin_m), 1e-12));
  const Eigen::AlignedBox3d handle = knife.HandleBounds(0.0);
  CHECK(handle.sizes().isApprox(geometry.handle_size_m, 1e-12));
  CHECK(handle.center().isApprox(geometry.handle_center_in_tcp_m, 1e-12));

  knife.SetMotion({SomePose(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
  blade = knife.BladeBounds(0.0);
  const Eigen::AlignedBox3d handle_moved = knife.HandleBounds(0.0);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::AlignedBox3d blade_samples, handle_samples;
  int blade_inside = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d p = knife.motion().pose * Eigen::Vector3d(0.1 * u(rng), 0.001 * u(rng),
                                                                    -0.0225 + 0.0225 * u(rng));
    if (knife.Blade(p).distance_m <= 0.0) {
      ++blade_inside;
      blade_samples.extend(p);
      CHECK(blade.contains(p));
    }
    const Eigen::Vector3d q =
        knife.motion().pose *
        (geometry.handle_center_in_tcp_m +
         0.5 * geometry.handle_size_m.cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng))));
    REQUIRE(knife.Handle(q).distance_m <= 1e-12);
    handle_samples.extend(q);
    CHECK(handle_moved.contains(q));
  }
  CHECK(blade_inside > 10000);
  // Tight: the parts' own corners (on their surfaces) span the boxes; only the bevel's taper
  // leaves the box a little larger than the blade.
  const double half_m = 0.5 * knife.effective_thickness_m();
  for (double x : {-0.1, 0.1}) {
    for (const Eigen::Vector2d& yz :
         {Eigen::Vector2d(-half_m, -0.045), Eigen::Vector2d(half_m, -0.045),
          Eigen::Vector2d(half_m, -0.008), Eigen::Vector2d(-half_m, -0.008),
          Eigen::Vector2d(0.1 * half_m, 0.0), Eigen::Vector2d(-0.1 * half_m, 0.0)}) {
      const Eigen::Vector3d corner = knife.motion().pose * Eigen::Vector3d(x, yz.x(), yz.y());
      CHECK(knife.Blade(corner).distance_m == Approx(0.0).margin(1e-12));
      blade_samples.extend(corner);
    }
  }
  CHECK(blade.contains(blade_samples));
  CHECK((blade.sizes() - blade_samples.sizes()).maxCoeff() < 2.0 * half_m);
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d sign((c & 1) ? 1.0 : -1.0, (c & 2) ? 1.0 : -1.0, (c & 4) ? 1.0 : -1.0);
    const Eigen::Vector3d corner =
        knife.motion().pose *
        (geometry.handle_center_in_tcp_m + 0.5 * geometry.handle_size_m.cwiseProduct(sign));
    CHECK(knife.Handle(corner).distance_m == Approx(0.0).margin(1e-12));
    handle_samples.extend(corner);
  }
  CHECK(handle_samples.min().isApprox(handle_moved.min(), 1e-12));
  CHECK(handle_samples.max().isApprox(handle_moved.max(), 1e-12));
}

TEST_CASE("box SDF is exact at faces, edges, corners and inside", "[mpm][colliders]") {
  const RigidMotion at_origin;
  const BoxSdf box(Eigen::Vector3d(0.4, 0.3, 0.02), at_origin);  // a cutting board
  SdfSample s = box.Sample({0.05, 0.02, 0.01 + 0.003});          // above the top face
  CHECK(s.distance_m == Approx(0.003));
  CHECK(s.normal.isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  s = box.Sample({0.2 + 0.003, 0.0, 0.01 + 0.004});  // beyond an edge
  CHECK(s.distance_m == Approx(0.005));
  CHECK(s.normal.isApprox(Eigen::Vector3d(0.6, 0.0, 0.8), 1e-12));
  s = box.Sample({-0.2 - 0.001, -0.15 - 0.002, -0.01 - 0.002});  // beyond a corner
  CHECK(s.distance_m == Approx(0.003));
  CHECK(s.normal.isApprox(Eigen::Vector3d(-1.0, -2.0, -2.0) / 3.0, 1e-12));
  s = box.Sample({0.1, 0.1, 0.007});  // inside, nearest the top face
  CHECK(s.distance_m == Approx(-0.003));
  CHECK(s.normal.isApprox(Eigen::Vector3d::UnitZ(), 1e-12));
  s = box.Sample({0.195, -0.1, 0.0});  // inside, nearest the +x face
  CHECK(s.distance_m == Approx(-0.005));
  CHECK(s.normal.isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  CHECK(box.Sample({0.2, 0.0, 0.0}).distance_m == Approx(0.0).margin(1e-15));

  // Moved: the same local points, rotated normals; the bounds hold the rotated corners.
  RigidMotion motion;
  motion.pose = SomePose();
  const BoxSdf moved(Eigen::Vector3d(0.4, 0.3, 0.02), motion);
  s = moved.Sample(motion.pose * Eigen::Vector3d(-0.201, -0.152, -0.012));
  CHECK(s.distance_m == Approx(0.003));
  CHECK(s.normal.isApprox(motion.pose.linear() * Eigen::Vector3d(-1.0, -2.0, -2.0) / 3.0, 1e-12));
  const Eigen::AlignedBox3d bounds = moved.Bounds(0.001);
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d corner((c & 1) ? 0.2 : -0.2, (c & 2) ? 0.15 : -0.15,
                                 (c & 4) ? 0.01 : -0.01);
    CHECK(bounds.contains(motion.pose * corner));
    CHECK(moved.Sample(motion.pose * corner).distance_m == Approx(0.0).margin(1e-12));
  }
  CHECK(box.Bounds(0.001).sizes().isApprox(Eigen::Vector3d(0.402, 0.302, 0.022), 1e-12));
}

TEST_CASE("the box's inside test agrees with its SDF's sign, also after the box moves", "[mpm][colliders]") {
  // The grid update asks Contains before it samples the board: the two must never disagree.
  RigidMotion motion;
  motion.pose = SomePose();
  BoxSdf box(Eigen::Vector3d(0.4, 0.3, 0.02), RigidMotion{});
  std::mt19937 random(7);
  std::uniform_real_distribution<double> local(-0.22, 0.22);
  int inside = 0;
  for (int pose = 0; pose < 2; ++pose) {
    for (int i = 0; i < 20000; ++i) {
      // Points near the faces of the 2 cm thin box (z squeezed towards it) as well as far from it.
      const Eigen::Vector3d p(local(random), local(random), 0.1 * local(random));
      const Eigen::Vector3d world = box.motion().pose * p;
      const bool contains = box.Contains(world);
      CHECK(contains == (box.Sample(world).distance_m < 0.0));
      inside += contains;
    }
    box.SetMotion(motion);  // the second round with the box turned and moved
  }
  CHECK(inside > 4000);  // both answers were exercised
  CHECK_FALSE(box.Contains(motion.pose * Eigen::Vector3d(0.2, 0.0, 0.0)));  // on a face: not inside
}

TEST_CASE("the table is the half-space below its height", "[mpm][colliders]") {
  const HalfSpaceSdf table(0.75);
  CHECK(table.Sample({1.0, -2.0, 0.8}).distance_m == Approx(0.05));
  CHECK(table.Sample({0.0, 0.0, 0.7}).distance_m == Approx(-0.05));
}

TEST_CASE("a spinning knife's velocity is v + w x r", "[mpm][colliders]") {
  KnifeSdf knife = DefaultKnife();
  RigidMotion motion;
  motion.pose = SomePose();
  motion.linear_velocity_m_s = Eigen::Vector3d(0.0, 0.0, -0.05);
  motion.angular_velocity_rad_s = Eigen::Vector3d(0.3, -1.0, 2.0);
  knife.SetMotion(motion);
  const Eigen::Vector3d tip = knife.motion().pose * Eigen::Vector3d(0.1, 0.0, 0.0);
  const Eigen::Vector3d r = tip - motion.pose.translation();
  const Eigen::Vector3d expected(-1.0 * r.z() - 2.0 * r.y(), 2.0 * r.x() - 0.3 * r.z(),
                                 -0.05 + 0.3 * r.y() + 1.0 * r.x());
  CHECK((knife.motion().VelocityAt(tip) - expected).norm() < 1e-12);
  // At the TCP itself only the linear velocity remains.
  CHECK(knife.motion().VelocityAt(motion.pose.translation()).isApprox(motion.linear_velocity_m_s));
}

}  // namespace
}  // namespace culinarycut::mpm
