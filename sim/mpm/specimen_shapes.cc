#include "sim/mpm/specimen_shapes.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace culinarycut::mpm {
namespace {

// Sampling only needs the sign; the max of the parts' distances is exact outside edges and corners.
class BoxSpecimen : public FoodShape {
 public:
  explicit BoxSpecimen(const Eigen::Vector3d& size_m) : half_m_(0.5 * size_m) {}
  double SignedDistance(const Eigen::Vector3d& local_m) const override {
    return (local_m.cwiseAbs() - half_m_).maxCoeff();
  }
  Eigen::AlignedBox3d LocalBounds() const override { return Eigen::AlignedBox3d(-half_m_, half_m_); }
  std::string food() const override { return "box"; }

 private:
  Eigen::Vector3d half_m_;
};

// Axis along local x; the flat face is the bounding box's bottom (z = -radius / 2), the disc's
// centre in the middle of that face.
class HalfCylinderSpecimen : public FoodShape {
 public:
  HalfCylinderSpecimen(double length_m, double radius_m) : half_length_m_(0.5 * length_m), radius_m_(radius_m) {}
  double SignedDistance(const Eigen::Vector3d& local_m) const override {
    const double bottom_m = -0.5 * radius_m_;
    const double round = std::hypot(local_m.y(), local_m.z() - bottom_m) - radius_m_;
    const double flat = bottom_m - local_m.z();
    const double ends = std::abs(local_m.x()) - half_length_m_;
    return std::max({round, flat, ends});
  }
  Eigen::AlignedBox3d LocalBounds() const override {
    const Eigen::Vector3d half(half_length_m_, radius_m_, 0.5 * radius_m_);
    return Eigen::AlignedBox3d(-half, half);
  }
  std::string food() const override { return "half_cylinder"; }

 private:
  double half_length_m_;
  double radius_m_;
};

}  // namespace

std::vector<std::string> SpecimenShapeNames() { return {"box", "half_cylinder"}; }

std::unique_ptr<FoodShape> MakeSpecimenShape(const std::string& kind, const Eigen::Vector3d& size_m) {
  if (!size_m.allFinite() || !(size_m.minCoeff() > 0.0)) {
    throw std::invalid_argument("specimen size_m must be three finite lengths > 0");
  }
  if (kind == "box") return std::make_unique<BoxSpecimen>(size_m);
  if (kind == "half_cylinder") {
    if (std::abs(size_m.y() - 2.0 * size_m.z()) > 1e-9 * size_m.y()) {
      throw std::invalid_argument("a half_cylinder's size_m is (length, 2 radius, radius): its width must be twice its height");
    }
    return std::make_unique<HalfCylinderSpecimen>(size_m.x(), size_m.z());
  }
  throw std::invalid_argument("unknown specimen '" + kind + "'; specimens: box, half_cylinder");
}

}  // namespace culinarycut::mpm
