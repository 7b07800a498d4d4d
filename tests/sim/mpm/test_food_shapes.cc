#include "sim/mpm/food_shapes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <catch2/catch.hpp>

#include "sim/mpm/sdf_primitives.h"

namespace culinarycut::mpm {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Analytic volumes of the shapes at scale 1 (m^3), from the sizes in food_shapes.cc.
double AnalyticVolume(const std::string& food) {
  const double sphere = 4.0 / 3.0 * kPi;
  if (food == "orange") return sphere * std::pow(0.0375, 3);
  if (food == "peach") return sphere * std::pow(0.035, 3);
  if (food == "apple") return sphere * 0.04 * 0.04 * 0.036;
  if (food == "melon") return sphere * 0.10 * 0.075 * 0.075;
  if (food == "cucumber") return kPi * 0.02 * 0.02 * (0.20 - 0.04) + sphere * std::pow(0.02, 3);
  if (food == "banana") {
    // Pappus: tube area times the arc length, plus the two hemispherical caps.
    const double r = 0.0175, arc_r = 0.10;
    const double half_angle = std::asin((0.09 - r) / arc_r);
    return kPi * r * r * 2.0 * half_angle * arc_r + sphere * r * r * r;
  }
  if (food == "strawberry") {
    // Round cone: shoulder sphere less its cap past the tangent circle, frustum, tip cap.
    const double r0 = 0.0125, r1 = 0.004, h = 0.035 - r0 - r1;
    const double b = (r0 - r1) / h, a = std::sqrt(1.0 - b * b);
    auto cap = [](double radius, double height) {
      return kPi * height * height * (3.0 * radius - height) / 3.0;
    };
    const double frustum_h = h + (r1 - r0) * b;
    const double frustum = kPi * frustum_h / 3.0 * (r0 * r0 + r0 * r1 + r1 * r1) * a * a;
    return sphere * r0 * r0 * r0 - cap(r0, r0 * (1.0 - b)) + frustum + cap(r1, r1 * (1.0 - b));
  }
  return 0.0;
}

Eigen::Vector3d RandomIn(const Eigen::AlignedBox3d& box, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::Vector3d u(unit(rng), unit(rng), unit(rng));
  return box.min() + box.sizes().cwiseProduct(u);
}

Eigen::Vector3d Gradient(const FoodShape& shape, const Eigen::Vector3d& p) {
  const double h = 1e-6;
  Eigen::Vector3d g;
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(axis);
    g[axis] = (shape.SignedDistance(p + e) - shape.SignedDistance(p - e)) / (2.0 * h);
  }
  return g;
}

Eigen::Isometry3d TiltedPose() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(-0.3, Eigen::Vector3d(1.0, 1.0, 0.0).normalized()))
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.45, -0.12, 0.81);
  return pose;
}

TEST_CASE("every food shape is named, negative inside and positive outside", "[mpm][food]") {
  REQUIRE(FoodShapeNames().size() == 7);
  for (const std::string& food : FoodShapeNames()) {
    INFO(food);
    const auto shape = MakeFoodShape(food);
    CHECK(shape->food() == food);
    CHECK(shape->SignedDistance(Eigen::Vector3d::Zero()) < 0.0);
    // Just past each face and corner of the bounds is outside.
    const Eigen::AlignedBox3d bounds = shape->LocalBounds();
    const Eigen::Vector3d half = 0.5 * bounds.sizes() + Eigen::Vector3d::Constant(1e-4);
    for (int axis = 0; axis < 3; ++axis) {
      for (double side : {-1.0, 1.0}) {
        const Eigen::Vector3d p = bounds.center() + side * half[axis] * Eigen::Vector3d::Unit(axis);
        CHECK(shape->SignedDistance(p) > 0.0);
      }
    }
    CHECK(shape->SignedDistance(bounds.center() + half) > 0.0);
    CHECK(shape->SignedDistance(bounds.center() - half) > 0.0);
    CHECK(shape->SignedDistance(Eigen::Vector3d(1.0, 1.0, 1.0)) > 1.0);
  }
  CHECK_THROWS_WITH(MakeFoodShape("tofu"), Catch::Contains("shapes: banana, cucumber"));
  CHECK_THROWS_WITH(MakeFoodShape("apple", 0.0), Catch::Contains("scale"));
  CHECK_THROWS_WITH(MakeFoodShape("apple", std::nan("")), Catch::Contains("scale"));
}

TEST_CASE("food bounds are tight: each face touches the shape within 1 mm", "[mpm][food]") {
  for (const std::string& food : FoodShapeNames()) {
    INFO(food);
    const auto shape = MakeFoodShape(food);
    const Eigen::AlignedBox3d bounds = shape->LocalBounds();
    CHECK(bounds.center().norm() < 1e-12);  // origin at the bounding box centre
    constexpr int kGrid = 100;
    for (int axis = 0; axis < 3; ++axis) {
      for (int side = 0; side < 2; ++side) {
        const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
        double closest_m = std::numeric_limits<double>::infinity();
        for (int iu = 0; iu <= kGrid; ++iu) {
          for (int iv = 0; iv <= kGrid; ++iv) {
            Eigen::Vector3d p;
            p[axis] = side == 0 ? bounds.min()[axis] : bounds.max()[axis];
            p[u_axis] = bounds.min()[u_axis] + bounds.sizes()[u_axis] * iu / kGrid;
            p[v_axis] = bounds.min()[v_axis] + bounds.sizes()[v_axis] * iv / kGrid;
            closest_m = std::min(closest_m, shape->SignedDistance(p));
          }
        }
        CAPTURE(axis, side, closest_m);
        CHECK(closest_m > -1e-9);  // the face does not cut into the food
        CHECK(closest_m < 1e-3);   // and the food reaches it
      }
    }
  }
}

TEST_CASE("food distance has unit gradient near the surface", "[mpm][food]") {
  std::mt19937_64 rng(7);
  for (const std::string& food : FoodShapeNames()) {
    INFO(food);
    const auto shape = MakeFoodShape(food);
    Eigen::AlignedBox3d box = shape->LocalBounds();
    box.extend(box.max() + Eigen::Vector3d::Constant(0.003));
    box.extend(box.min() - Eigen::Vector3d::Constant(0.003));
    int tested = 0;
    double worst = 0.0;
    for (int attempt = 0; attempt < 200000 && tested < 300; ++attempt) {
      const Eigen::Vector3d p = RandomIn(box, rng);
      if (std::abs(shape->SignedDistance(p)) > 0.003) continue;
      worst = std::max(worst, std::abs(Gradient(*shape, p).norm() - 1.0));
      ++tested;
    }
    CAPTURE(tested, worst);
    CHECK(tested == 300);
    CHECK(worst < 0.1);
  }
}

TEST_CASE("ellipsoid distance is close to the true distance near the surface", "[mpm][food]") {
  // Brute force: nearest of a dense parametric surface grid, refined by pattern search.
  const Eigen::Vector3d radii(0.10, 0.075, 0.075);  // the melon
  auto surface = [&](double u, double v) {
    return Eigen::Vector3d(radii.x() * std::cos(u), radii.y() * std::sin(u) * std::cos(v),
                           radii.z() * std::sin(u) * std::sin(v));
  };
  std::mt19937_64 rng(3);
  const Eigen::AlignedBox3d box(-radii - Eigen::Vector3d::Constant(0.005),
                                radii + Eigen::Vector3d::Constant(0.005));
  double worst_m = 0.0;
  for (int tested = 0; tested < 20;) {
    const Eigen::Vector3d p = RandomIn(box, rng);
    const double approx_m = sdf::Ellipsoid(p, radii);
    if (std::abs(approx_m) > 0.005) continue;
    ++tested;
    double best = std::numeric_limits<double>::infinity(), bu = 0.0, bv = 0.0;
    constexpr int kN = 60;
    for (int i = 0; i <= kN; ++i) {
      for (int j = 0; j < 2 * kN; ++j) {
        const double u = kPi * i / kN, v = kPi * j / kN;
        const double d = (p - surface(u, v)).squaredNorm();
        if (d < best) best = d, bu = u, bv = v;
      }
    }
    for (double step = kPi / kN; step > 1e-9;) {
      bool improved = false;
      for (int du = -1; du <= 1; ++du) {
        for (int dv = -1; dv <= 1; ++dv) {
          const double d = (p - surface(bu + du * step, bv + dv * step)).squaredNorm();
          if (d < best) best = d, bu += du * step, bv += dv * step, improved = true;
        }
      }
      if (!improved) step *= 0.5;
    }
    const double exact_m = std::copysign(std::sqrt(best), approx_m);
    worst_m = std::max(worst_m, std::abs(approx_m - exact_m));
  }
  CAPTURE(worst_m);
  CHECK(worst_m < 5e-5);  // documented: < 0.012 mm within 5 mm of the melon's surface
}

TEST_CASE("scale multiplies every length of a food shape", "[mpm][food]") {
  std::mt19937_64 rng(11);
  for (const std::string& food : FoodShapeNames()) {
    INFO(food);
    const auto unit = MakeFoodShape(food, 1.0);
    const auto twice = MakeFoodShape(food, 2.0);
    const Eigen::AlignedBox3d b1 = unit->LocalBounds(), b2 = twice->LocalBounds();
    CHECK((b2.min() - 2.0 * b1.min()).norm() < 1e-12);
    CHECK((b2.max() - 2.0 * b1.max()).norm() < 1e-12);
    for (int n = 0; n < 50; ++n) {
      const Eigen::Vector3d p = RandomIn(b1, rng);
      CHECK(twice->SignedDistance(2.0 * p) == Approx(2.0 * unit->SignedDistance(p)).margin(1e-12));
    }
  }
}

TEST_CASE("sampled food volume matches the analytic volume at dx 2 mm, 8 per cell", "[mpm][food]") {
  SamplingOptions options;
  options.dx_m = 0.002;
  options.particles_per_cell = 8;
  for (const std::string& food : FoodShapeNames()) {
    // Half a melon's size keeps the particle count (and the test time) down.
    const double scale = food == "melon" ? 0.5 : 1.0;
    const auto shape = MakeFoodShape(food, scale);
    Particles<float> particles;
    const std::size_t count =
        SampleFood(*shape, Eigen::Isometry3d::Identity(), 1000.0, 0, 0, options, &particles);
    const double sampled_m3 = count * std::pow(options.dx_m, 3) / options.particles_per_cell;
    const double analytic_m3 = AnalyticVolume(food) * std::pow(scale, 3);
    const double relative_error = sampled_m3 / analytic_m3 - 1.0;
    CAPTURE(food, count, sampled_m3, analytic_m3, relative_error);
    // The brief asks for 5 %; stratified jitter gives under 0.2 % here.
    CHECK(std::abs(relative_error) < 0.01);
  }
}

TEST_CASE("a food's estimated volume matches its analytic volume", "[mpm][food]") {
  for (const std::string& food : FoodShapeNames()) {
    for (const double scale : {0.5, 1.0}) {
      const double relative_error = EstimatedVolume(*MakeFoodShape(food, scale)) / (AnalyticVolume(food) * std::pow(scale, 3)) - 1.0;
      CAPTURE(food, scale, relative_error);
      CHECK(std::abs(relative_error) < 0.02);
    }
  }
}

TEST_CASE("sampled particles lie inside the posed food with the right mass", "[mpm][food]") {
  const Eigen::Isometry3d pose = TiltedPose();
  const Eigen::Isometry3d to_local = pose.inverse();
  SamplingOptions options;
  options.dx_m = 0.003;
  options.particles_per_cell = 8;
  options.seed = 42;
  const double density = 950.0;
  for (const char* food : {"banana", "strawberry", "apple"}) {
    INFO(food);
    const auto shape = MakeFoodShape(food);
    Particles<float> particles;
    particles.Add({0.0f, 0.0f, 0.0f}, 1.0f, 1.0f, 9, 9);  // sampling appends after this one
    const std::size_t count = SampleFood(*shape, pose, density, 3, 5, options, &particles);
    REQUIRE(count > 100);
    REQUIRE(particles.size() == count + 1);
    const double volume_m3 = std::pow(options.dx_m, 3) / options.particles_per_cell;
    double mass_kg = 0.0;
    double worst_m = -1.0;
    double worst_volume_error = 0.0;
    std::size_t wrong_ids = 0;
    for (std::size_t p = 1; p < particles.size(); ++p) {
      const Eigen::Vector3d world(particles.position[0][p], particles.position[1][p],
                                  particles.position[2][p]);
      worst_m = std::max(worst_m, shape->SignedDistance(to_local * world));
      mass_kg += particles.mass[p];
      worst_volume_error =
          std::max(worst_volume_error, std::abs(particles.volume[p] / volume_m3 - 1.0));
      wrong_ids += particles.material[p] != 3 || particles.object[p] != 5;
    }
    CHECK(worst_m < 1e-6);  // float positions round by ~1e-7 m
    CHECK(worst_volume_error < 1e-6);
    CHECK(wrong_ids == 0);
    CHECK(mass_kg == Approx(density * count * volume_m3).epsilon(1e-5));
    CHECK(particles.object[0] == 9);
  }
}

TEST_CASE("food sampling is deterministic for a seed", "[mpm][food]") {
  const auto shape = MakeFoodShape("strawberry");
  SamplingOptions options;
  options.dx_m = 0.002;
  options.seed = 123;
  Particles<double> a, b, c;
  SampleFood(*shape, TiltedPose(), 900.0, 0, 0, options, &a);
  SampleFood(*shape, TiltedPose(), 900.0, 0, 0, options, &b);
  options.seed = 124;
  SampleFood(*shape, TiltedPose(), 900.0, 0, 0, options, &c);
  REQUIRE(a.size() > 0);
  CHECK(a.position == b.position);
  CHECK(a.mass == b.mass);
  CHECK(a.position != c.position);
}

TEST_CASE("particles per cell is configurable and the count scales with it", "[mpm][food]") {
  const auto shape = MakeFoodShape("orange");
  SamplingOptions options;
  options.dx_m = 0.003;
  options.particles_per_cell = 1;
  Particles<float> one;
  const double per_cell_1 =
      SampleFood(*shape, Eigen::Isometry3d::Identity(), 950.0, 0, 0, options, &one);
  for (int ppc : {2, 5, 8, 27, 64}) {
    options.particles_per_cell = ppc;
    Particles<float> many;
    const double per_cell =
        SampleFood(*shape, Eigen::Isometry3d::Identity(), 950.0, 0, 0, options, &many) /
        static_cast<double>(ppc);
    CAPTURE(ppc, per_cell, per_cell_1);
    CHECK(per_cell == Approx(per_cell_1).epsilon(0.03));
  }
}

TEST_CASE("the strata used in a cell spread over the whole cell", "[mpm][food]") {
  // An orange sits symmetrically in its centred grid: any one-sided choice of sub-cells would
  // shift the particles' centroid by a fraction of dx.
  const auto shape = MakeFoodShape("orange");
  SamplingOptions options;
  options.dx_m = 0.004;
  for (int ppc : {2, 4, 8, 16, 27}) {
    options.particles_per_cell = ppc;
    Particles<double> particles;
    SampleFood(*shape, Eigen::Isometry3d::Identity(), 950.0, 0, 0, options, &particles);
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (std::size_t p = 0; p < particles.size(); ++p) {
      centroid += Eigen::Vector3d(particles.position[0][p], particles.position[1][p],
                                  particles.position[2][p]);
    }
    centroid /= static_cast<double>(particles.size());
    CAPTURE(ppc, centroid.transpose());
    CHECK(centroid.cwiseAbs().maxCoeff() < 0.03 * options.dx_m);
  }
}

TEST_CASE("banana is curved in the horizontal plane", "[mpm][food]") {
  const auto shape = MakeFoodShape("banana");
  SamplingOptions options;
  options.dx_m = 0.003;
  Particles<double> particles;
  SampleFood(*shape, Eigen::Isometry3d::Identity(), 950.0, 0, 0, options, &particles);
  REQUIRE(particles.size() > 100);
  // Chord between the ends (centroids of the outer 1 cm along x); the centroid lies off it, in y.
  const auto& x = particles.position[0];
  const double min_x = *std::min_element(x.begin(), x.end());
  const double max_x = *std::max_element(x.begin(), x.end());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero(), a = centroid, b = centroid;
  int a_count = 0, b_count = 0;
  for (std::size_t p = 0; p < particles.size(); ++p) {
    const Eigen::Vector3d point(x[p], particles.position[1][p], particles.position[2][p]);
    centroid += point;
    if (x[p] < min_x + 0.01) a += point, ++a_count;
    if (x[p] > max_x - 0.01) b += point, ++b_count;
  }
  centroid /= static_cast<double>(particles.size());
  a /= a_count;
  b /= b_count;
  const Eigen::Vector3d chord = (b - a).normalized();
  const Eigen::Vector3d offset = (centroid - a) - (centroid - a).dot(chord) * chord;
  CAPTURE(offset.transpose());
  CHECK(std::abs(offset.y()) > 0.01);   // the bow, about 2 cm
  CHECK(std::abs(offset.z()) < 0.002);  // flat on the board: no bow in z
}

TEST_CASE("bad sampling options throw naming the field", "[mpm][food]") {
  const auto shape = MakeFoodShape("peach");
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  Particles<float> particles;
  auto sample = [&](const SamplingOptions& options) {
    return SampleFood(*shape, identity, 950.0, 0, 0, options, &particles);
  };
  for (double dx : {0.0, -0.001, std::nan(""), std::numeric_limits<double>::infinity(), 1e-7}) {
    SamplingOptions options;
    options.dx_m = dx;
    CAPTURE(dx);
    CHECK_THROWS_WITH(sample(options), Catch::Contains("dx_m"));
  }
  for (int ppc : {0, -1, 65}) {
    SamplingOptions options;
    options.particles_per_cell = ppc;
    CHECK_THROWS_WITH(sample(options), Catch::Contains("particles_per_cell"));
  }
  CHECK_THROWS_WITH(SampleFood(*shape, identity, 0.0, 0, 0, SamplingOptions(), &particles),
                    Catch::Contains("density_kg_m3"));
  Eigen::Isometry3d scaled = identity;
  scaled.linear() *= 1.1;
  CHECK_THROWS_WITH(SampleFood(*shape, scaled, 950.0, 0, 0, SamplingOptions(), &particles),
                    Catch::Contains("pose"));
  Eigen::Isometry3d mirrored = identity;
  mirrored.linear()(2, 2) = -1.0;
  CHECK_THROWS_WITH(SampleFood(*shape, mirrored, 950.0, 0, 0, SamplingOptions(), &particles),
                    Catch::Contains("pose"));
  CHECK_THROWS_WITH(SampleFood<float>(*shape, identity, 950.0, 0, 0, SamplingOptions(), nullptr),
                    Catch::Contains("particles"));
  CHECK(particles.size() == 0);  // nothing was added by a refused call
}

TEST_CASE("sdf helpers: rounded box and smooth union", "[mpm][food]") {
  const Eigen::Vector3d half(0.02, 0.01, 0.005);
  CHECK(sdf::RoundedBox(Eigen::Vector3d(0.03, 0.0, 0.0), half, 0.002) == Approx(0.01));
  CHECK(sdf::RoundedBox(Eigen::Vector3d::Zero(), half, 0.002) == Approx(-0.005));
  // A rounded corner: distance from the corner sphere's centre minus its radius.
  const Eigen::Vector3d corner_centre = half - Eigen::Vector3d::Constant(0.002);
  const Eigen::Vector3d p = corner_centre + 0.01 * Eigen::Vector3d::Ones().normalized();
  CHECK(sdf::RoundedBox(p, half, 0.002) == Approx(0.008));
  CHECK(sdf::SmoothUnion(0.01, 0.05, 0.004) == Approx(0.01));          // far apart: the minimum
  CHECK(sdf::SmoothUnion(0.01, 0.01, 0.004) == Approx(0.01 - 0.001));  // k/4 below in the blend
  CHECK(sdf::SmoothUnion(-0.002, 0.03, 0.0) == -0.002);
}

}  // namespace
}  // namespace culinarycut::mpm
