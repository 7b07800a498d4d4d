#include "sim/mpm/food_shapes.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>

#include "sim/mpm/sdf_primitives.h"

namespace culinarycut::mpm {
namespace {

// Typical sizes at scale 1 (m). Chosen from common produce; each shape lies with its long axis
// along local x and rests on the board with local z up.
constexpr double kCucumberLength = 0.20;   // tip to tip
constexpr double kCucumberRadius = 0.02;   // 40 mm across
constexpr double kBananaLength = 0.18;     // bounding-box length along x, end cap to end cap
constexpr double kBananaRadius = 0.0175;   // 35 mm thick
constexpr double kBananaArcRadius = 0.10;  // centre line curvature radius: ~31 mm of bow
constexpr double kAppleRadius = 0.04;      // 80 mm across
constexpr double kAppleHeight = 0.036;     // half height: slightly oblate, stem axis up
constexpr double kOrangeRadius = 0.0375;   // 75 mm across
constexpr double kPeachRadius = 0.035;     // 70 mm across
constexpr double kMelonHalfLength = 0.10;  // 200 x 150 x 150 mm
constexpr double kMelonRadius = 0.075;
constexpr double kStrawberryLength = 0.035;     // shoulder to tip
constexpr double kStrawberryShoulder = 0.0125;  // 25 mm across at the calyx
constexpr double kStrawberryTip = 0.004;        // rounded tip

class SphereFood : public FoodShape {
 public:
  SphereFood(std::string food, double radius_m) : food_(std::move(food)), radius_m_(radius_m) {}
  double SignedDistance(const Eigen::Vector3d& local_m) const override {
    return sdf::Sphere(local_m, radius_m_);
  }
  Eigen::AlignedBox3d LocalBounds() const override {
    const Eigen::Vector3d half = Eigen::Vector3d::Constant(radius_m_);
    return Eigen::AlignedBox3d(-half, half);
  }
  std::string food() const override { return food_; }

 private:
  std::string food_;
  double radius_m_;
};

class EllipsoidFood : public FoodShape {
 public:
  EllipsoidFood(std::string food, const Eigen::Vector3d& radii_m)
      : food_(std::move(food)), radii_m_(radii_m) {}
  double SignedDistance(const Eigen::Vector3d& local_m) const override {
    return sdf::Ellipsoid(local_m, radii_m_);
  }
  Eigen::AlignedBox3d LocalBounds() const override {
    return Eigen::AlignedBox3d(-radii_m_, radii_m_);
  }
  std::string food() const override { return food_; }

 private:
  std::string food_;
  Eigen::Vector3d radii_m_;
};

class CapsuleFood : public FoodShape {
 public:
  CapsuleFood(std::string food, double length_m, double radius_m)
      : food_(std::move(food)), half_length_m_(0.5 * length_m - radius_m), radius_m_(radius_m) {}
  double SignedDistance(const Eigen::Vector3d& local_m) const override {
    return sdf::CapsuleX(local_m, half_length_m_, radius_m_);
  }
  Eigen::AlignedBox3d LocalBounds() const override {
    const Eigen::Vector3d half(half_length_m_ + radius_m_, radius_m_, radius_m_);
    return Eigen::AlignedBox3d(-half, half);
  }
  std::string food() const override { return food_; }

 private:
  std::string food_;
  double half_length_m_;
  double radius_m_;
};

// A capsule bent along a circular arc in the horizontal x-y plane, so that it rests flat on the
// board; it bows towards -y (ends at larger y than the middle). Constant thickness: no taper.
class BananaFood : public FoodShape {
 public:
  BananaFood(double length_m, double radius_m, double arc_radius_m)
      : radius_m_(radius_m), arc_radius_m_(arc_radius_m) {
    // The x extent is set by the end caps: 2 (R sin(a) + r) = length.
    half_angle_rad_ = std::asin((0.5 * length_m - radius_m) / arc_radius_m);
    // y spans [c - R - r, c - R cos(a) + r] for the arc's circle centre at y = c; centre it.
    centre_y_m_ = 0.5 * arc_radius_m * (1.0 + std::cos(half_angle_rad_));
  }
  double SignedDistance(const Eigen::Vector3d& local_m) const override {
    return sdf::ArcCapsuleXY(local_m - Eigen::Vector3d(0.0, centre_y_m_, 0.0), arc_radius_m_,
                             half_angle_rad_, radius_m_);
  }
  Eigen::AlignedBox3d LocalBounds() const override {
    const double half_x = arc_radius_m_ * std::sin(half_angle_rad_) + radius_m_;
    const double half_y = centre_y_m_ - arc_radius_m_ * std::cos(half_angle_rad_) + radius_m_;
    return Eigen::AlignedBox3d(Eigen::Vector3d(-half_x, -half_y, -radius_m_),
                               Eigen::Vector3d(half_x, half_y, radius_m_));
  }
  std::string food() const override { return "banana"; }

 private:
  double radius_m_;
  double arc_radius_m_;
  double half_angle_rad_;
  double centre_y_m_;
};

// Round cone: the wide shoulder (calyx end) at -x, the rounded tip at +x. It lies as a cone at rest
// does, on the line along its side: the axis dips towards the tip by the cone's half angle, so both
// end spheres touch the board. With the axis level it would rest on the shoulder alone, tip in the
// air, and roll some 6 mm forward onto its side when the knife wakes the food.
class StrawberryFood : public FoodShape {
 public:
  StrawberryFood(double length_m, double shoulder_radius_m, double tip_radius_m)
      : shoulder_m_(shoulder_radius_m), tip_m_(tip_radius_m), axis_length_m_(length_m - shoulder_radius_m - tip_radius_m) {
    const double dip_rad = std::asin((shoulder_m_ - tip_m_) / axis_length_m_);  // the half angle
    to_axis_frame_ = Eigen::AngleAxisd(-dip_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
    // The sphere centres with the shoulder's at the origin, then the shape centred on its box.
    const Eigen::Vector3d tip_centre_m = to_axis_frame_.transpose() * Eigen::Vector3d(axis_length_m_, 0.0, 0.0);
    const Eigen::Vector3d r0 = Eigen::Vector3d::Constant(shoulder_m_), r1 = Eigen::Vector3d::Constant(tip_m_);
    Eigen::AlignedBox3d box(-r0, r0);
    box.extend(Eigen::AlignedBox3d(tip_centre_m - r1, tip_centre_m + r1));
    shoulder_centre_m_ = -box.center();
    half_extent_m_ = 0.5 * box.sizes();
  }
  double SignedDistance(const Eigen::Vector3d& local_m) const override {
    return sdf::RoundConeX(to_axis_frame_ * (local_m - shoulder_centre_m_), shoulder_m_, tip_m_, axis_length_m_);
  }
  Eigen::AlignedBox3d LocalBounds() const override {
    // A round cone is the hull of its two spheres, so their boxes bound it tightly.
    return Eigen::AlignedBox3d(-half_extent_m_, half_extent_m_);
  }
  std::string food() const override { return "strawberry"; }

 private:
  double shoulder_m_;
  double tip_m_;
  double axis_length_m_;
  Eigen::Matrix3d to_axis_frame_;       // local frame -> the cone's (axis along +x)
  Eigen::Vector3d shoulder_centre_m_;   // in the local frame
  Eigen::Vector3d half_extent_m_;
};

// Uniform in [0, 1) from the top 53 bits: the same on every platform (std::uniform_real_
// distribution is not specified bit-for-bit).
double Uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// The order in which a cell's strata^3 sub-cells are used: greedy farthest point on the periodic
// sub-grid (ties: larger summed distance, then lower index), so that the first ppc of them spread
// over the whole cell; lexicographic order would fill one side of the cell first.
std::vector<int> StratumOrder(int strata) {
  const int count = strata * strata * strata;
  auto distance2 = [strata](int a, int b) {
    int sum = 0;
    for (int stride = 1; stride < strata * strata * strata; stride *= strata) {
      const int d = std::abs((a / stride) % strata - (b / stride) % strata);
      sum += std::min(d, strata - d) * std::min(d, strata - d);
    }
    return sum;
  };
  std::vector<int> order = {0};
  std::vector<bool> used(count, false);
  used[0] = true;
  while (static_cast<int>(order.size()) < count) {
    int best = -1, best_min = -1;
    double best_sum = -1.0;
    for (int candidate = 0; candidate < count; ++candidate) {
      if (used[candidate]) continue;
      int min_d2 = std::numeric_limits<int>::max();
      double sum = 0.0;
      for (int chosen : order) {
        const int d2 = distance2(candidate, chosen);
        min_d2 = std::min(min_d2, d2);
        sum += std::sqrt(static_cast<double>(d2));
      }
      if (min_d2 > best_min || (min_d2 == best_min && sum > best_sum)) {
        best = candidate, best_min = min_d2, best_sum = sum;
      }
    }
    used[best] = true;
    order.push_back(best);
  }
  return order;
}

void ValidateSampling(const Eigen::Isometry3d& pose, double density_kg_m3,
                      const SamplingOptions& options, const void* particles) {
  if (!(options.dx_m > 0.0 && std::isfinite(options.dx_m))) {
    throw std::invalid_argument("SampleFood: dx_m must be finite and > 0");
  }
  if (options.particles_per_cell < 1 || options.particles_per_cell > 64) {
    throw std::invalid_argument("SampleFood: particles_per_cell must lie in [1, 64]");
  }
  if (!(density_kg_m3 > 0.0 && std::isfinite(density_kg_m3))) {
    throw std::invalid_argument("SampleFood: density_kg_m3 must be finite and > 0");
  }
  const Eigen::Matrix3d rotation = pose.linear();
  const double orthogonality =
      (rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  // A scale or reflection in the pose would change the particles' volume or mirror the food.
  if (!pose.matrix().allFinite() || !(orthogonality < 1e-6) || !(rotation.determinant() > 0.0)) {
    throw std::invalid_argument("SampleFood: pose must be a rotation plus a translation");
  }
  if (particles == nullptr) throw std::invalid_argument("SampleFood: particles is null");
}

}  // namespace

std::vector<std::string> FoodShapeNames() {
  return {"banana", "cucumber", "apple", "peach", "melon", "orange", "strawberry"};
}

std::unique_ptr<FoodShape> MakeFoodShape(const std::string& food, double scale) {
  if (!(scale > 0.0 && std::isfinite(scale))) {
    throw std::invalid_argument("MakeFoodShape: scale must be finite and > 0");
  }
  const double s = scale;
  if (food == "banana") {
    return std::make_unique<BananaFood>(s * kBananaLength, s * kBananaRadius, s * kBananaArcRadius);
  }
  if (food == "cucumber") {
    return std::make_unique<CapsuleFood>("cucumber", s * kCucumberLength, s * kCucumberRadius);
  }
  if (food == "apple") {
    return std::make_unique<EllipsoidFood>(
        "apple", s * Eigen::Vector3d(kAppleRadius, kAppleRadius, kAppleHeight));
  }
  if (food == "peach") return std::make_unique<SphereFood>("peach", s * kPeachRadius);
  if (food == "melon") {
    return std::make_unique<EllipsoidFood>(
        "melon", s * Eigen::Vector3d(kMelonHalfLength, kMelonRadius, kMelonRadius));
  }
  if (food == "orange") return std::make_unique<SphereFood>("orange", s * kOrangeRadius);
  if (food == "strawberry") {
    return std::make_unique<StrawberryFood>(s * kStrawberryLength, s * kStrawberryShoulder,
                                            s * kStrawberryTip);
  }
  std::string names;
  for (const std::string& name : FoodShapeNames()) names += (names.empty() ? "" : ", ") + name;
  throw std::invalid_argument("MakeFoodShape: unknown food '" + food + "'; shapes: " + names);
}

double EstimatedVolume(const FoodShape& shape) {
  constexpr int kLattice = 48;
  const Eigen::AlignedBox3d bounds = shape.LocalBounds();
  const Eigen::Vector3d step_m = bounds.sizes() / kLattice;
  int inside = 0;
  for (int k = 0; k < kLattice; ++k) {
    for (int j = 0; j < kLattice; ++j) {
      for (int i = 0; i < kLattice; ++i) {
        const Eigen::Vector3d local_m = bounds.min() + step_m.cwiseProduct(Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5));
        if (shape.SignedDistance(local_m) < 0.0) ++inside;
      }
    }
  }
  return inside * step_m.prod();
}

template <typename Real>
std::size_t SampleFood(const FoodShape& shape, const Eigen::Isometry3d& pose, double density_kg_m3,
                       std::uint16_t material_id, std::uint16_t object_id,
                       const SamplingOptions& options, Particles<Real>* particles) {
  ValidateSampling(pose, density_kg_m3, options, particles);
  const double dx = options.dx_m;
  const int ppc = options.particles_per_cell;

  // Cells cover the bounds, centred on them so that a symmetric shape samples symmetrically.
  const Eigen::AlignedBox3d bounds = shape.LocalBounds();
  const Eigen::Vector3d extent = bounds.sizes();
  const Eigen::Vector3d cell_counts = (extent / dx).array().ceil().max(1.0).matrix();
  // Guards against a dx far too small for the shape (billions of candidate points).
  if (cell_counts.prod() * ppc > 2.0e9) {
    throw std::invalid_argument("SampleFood: dx_m is too small for the shape (over 2e9 points)");
  }
  const long long cells[3] = {static_cast<long long>(cell_counts.x()),
                              static_cast<long long>(cell_counts.y()),
                              static_cast<long long>(cell_counts.z())};
  const Eigen::Vector3d origin = bounds.center() - 0.5 * dx * cell_counts;

  // Stratified jitter: a strata^3 sub-grid per cell, the first ppc strata of a spread order.
  int strata = 1;
  while (strata * strata * strata < ppc) ++strata;
  const std::vector<int> stratum_order = StratumOrder(strata);

  const double volume_m3 = dx * dx * dx / ppc;
  const Real particle_volume = static_cast<Real>(volume_m3);
  const Real particle_mass = static_cast<Real>(density_kg_m3 * volume_m3);
  std::mt19937_64 rng(options.seed);
  std::size_t added = 0;
  // Fixed order (z, y, x cells, then strata, then x, y, z draws) and three draws per candidate
  // whether kept or not: the particles depend on the seed alone.
  for (long long k = 0; k < cells[2]; ++k) {
    for (long long j = 0; j < cells[1]; ++j) {
      for (long long i = 0; i < cells[0]; ++i) {
        for (int n = 0; n < ppc; ++n) {
          const int stratum = stratum_order[n];
          const int sx = stratum % strata;
          const int sy = (stratum / strata) % strata;
          const int sz = stratum / (strata * strata);
          const double ux = Uniform01(rng);
          const double uy = Uniform01(rng);
          const double uz = Uniform01(rng);
          const Eigen::Vector3d local =
              origin + dx * Eigen::Vector3d(static_cast<double>(i) + (sx + ux) / strata,
                                            static_cast<double>(j) + (sy + uy) / strata,
                                            static_cast<double>(k) + (sz + uz) / strata);
          if (!(shape.SignedDistance(local) < 0.0)) continue;
          const Eigen::Vector3d world = pose * local;
          particles->Add({static_cast<Real>(world.x()), static_cast<Real>(world.y()),
                          static_cast<Real>(world.z())},
                         particle_mass, particle_volume, material_id, object_id);
          ++added;
        }
      }
    }
  }
  return added;
}

template std::size_t SampleFood<float>(const FoodShape&, const Eigen::Isometry3d&, double,
                                       std::uint16_t, std::uint16_t, const SamplingOptions&,
                                       Particles<float>*);
template std::size_t SampleFood<double>(const FoodShape&, const Eigen::Isometry3d&, double,
                                        std::uint16_t, std::uint16_t, const SamplingOptions&,
                                        Particles<double>*);

}  // namespace culinarycut::mpm
