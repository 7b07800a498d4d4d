#include "sim/task/cut_plane_fit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

namespace culinarycut::task {
namespace {

// Refits on the material within this quantile of each side's distance to the plane: the slab the
// blade labelled is clipped by the food's outline, which tilts the first fit; the material next to
// the plane is clipped least.
constexpr double kNearPlaneQuantile = 0.5;
constexpr int kRefinements = 2;

struct SideMoments {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();  // sum of (x - mean)(x - mean)^T, m^2
  std::size_t count = 0;
};

SideMoments MomentsOf(const std::vector<Eigen::Vector3d>& points, const std::vector<bool>& keep) {
  SideMoments moments;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!keep[i]) continue;
    moments.mean += points[i];
    ++moments.count;
  }
  if (moments.count == 0) return moments;
  moments.mean /= double(moments.count);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!keep[i]) continue;
    const Eigen::Vector3d offset = points[i] - moments.mean;
    moments.scatter += offset * offset.transpose();
  }
  return moments;
}

// Fisher's direction S_w^-1 (mean+ - mean-), S_w the pooled scatter; nullopt when the means coincide.
std::optional<FittedPlane> Discriminant(const SideMoments& positive, const SideMoments& negative) {
  const Eigen::Vector3d between = positive.mean - negative.mean;
  if (!(between.norm() > 0.0)) return std::nullopt;
  const Eigen::Matrix3d pooled = positive.scatter + negative.scatter;
  // A tiny ridge keeps flat point sets (all in one plane) solvable without changing a real fit.
  const double ridge = 1e-12 * std::max(pooled.trace(), 1e-12);
  Eigen::Vector3d direction = (pooled + ridge * Eigen::Matrix3d::Identity()).ldlt().solve(between);
  if (!direction.allFinite() || !(direction.norm() > 0.0)) direction = between;
  direction.normalize();
  if (direction.dot(between) < 0.0) direction = -direction;
  return FittedPlane{0.5 * (positive.mean + negative.mean), direction};
}

// Keeps the points of one side whose distance to `plane` is within the side's quantile.
std::vector<bool> NearPlane(const std::vector<Eigen::Vector3d>& points, const FittedPlane& plane) {
  std::vector<double> distance(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) distance[i] = std::abs((points[i] - plane.point_m).dot(plane.normal));
  std::vector<double> sorted = distance;
  const std::size_t rank = std::min(sorted.size() - 1, std::size_t(kNearPlaneQuantile * double(sorted.size())));
  std::nth_element(sorted.begin(), sorted.begin() + rank, sorted.end());
  std::vector<bool> keep(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) keep[i] = distance[i] <= sorted[rank];
  return keep;
}

}  // namespace

std::optional<FittedPlane> FitCutPlane(const std::vector<Eigen::Vector3d>& positive,
                                       const std::vector<Eigen::Vector3d>& negative) {
  if (positive.size() < kMinPointsPerSide || negative.size() < kMinPointsPerSide) return std::nullopt;
  std::optional<FittedPlane> plane = Discriminant(MomentsOf(positive, std::vector<bool>(positive.size(), true)),
                                                  MomentsOf(negative, std::vector<bool>(negative.size(), true)));
  for (int pass = 0; pass < kRefinements && plane; ++pass) {
    const SideMoments near_positive = MomentsOf(positive, NearPlane(positive, *plane));
    const SideMoments near_negative = MomentsOf(negative, NearPlane(negative, *plane));
    if (near_positive.count < kMinPointsPerSide || near_negative.count < kMinPointsPerSide) break;
    const std::optional<FittedPlane> refined = Discriminant(near_positive, near_negative);
    if (!refined) break;
    plane = refined;
  }
  return plane;
}

}  // namespace culinarycut::task
